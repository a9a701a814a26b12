#!/usr/bin/env python3
"""The report of a replay (replay_bag's output folder): report.html, self-contained (PNG plots
embedded as base64), and a short episode table on stdout.

    replay_report.py OUT_DIR [--max-pairs N]

The page has: a summary (bag, configuration, cycles, tracks, dropped boxes by reason, the
speed scale's minimum, mean and protective stops, DEGRADED intervals with their reasons), the
smallest time to contact over the whole scene per cycle, the speed scale per cycle (speed and
separation monitoring), a table of episodes (pair, start, end, peak level, smallest time to
contact and distance), and a timeline per pair (time to contact and distance over bag time,
coloured by level). Also writes the plots as PNG files next to the page (min_ttc.png,
speed_scale.png, timelines.png).
"""
import argparse
import base64
import html
import io
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import replay_data  # noqa: E402

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

COLOURS = {"NOTICE": "#2a9d8f", "WARNING": "#f4a261", "CRITICAL": "#d62828"}
DEGRADED_COLOUR = "#adb5bd"


def png(fig, path):
    """The figure as PNG bytes, also saved to `path`."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    data = buf.getvalue()
    with open(path, "wb") as f:
        f.write(data)
    return data


def shade_degraded(ax, intervals):
    for start, end, _ in intervals:
        ax.axvspan(start, end, color=DEGRADED_COLOUR, alpha=0.35, lw=0)


def level_legend():
    return [Line2D([], [], marker="o", ls="", color=COLOURS[l], label=l) for l in replay_data.LEVELS]


def min_ttc_plot(cycles, events_by_cycle, horizon, duration, intervals, path):
    """Smallest time to contact of each cycle over the scene, coloured by that event's level."""
    fig, ax = plt.subplots(figsize=(11, 3.6))
    shade_degraded(ax, intervals)
    for level in replay_data.LEVELS:
        ts, vs = [], []
        for c in cycles:
            best = events_by_cycle.get(c["stamp"])
            if best is not None and best.level == level:
                ts.append(c["t"])
                vs.append(best.time_to_contact)
        ax.scatter(ts, vs, s=6, color=COLOURS[level], label=level, zorder=3)
    # The same as a thin line, broken where nothing is predicted.
    ts = [c["t"] for c in cycles]
    vs = [events_by_cycle[c["stamp"]].time_to_contact if c["stamp"] in events_by_cycle else math.nan
          for c in cycles]
    ax.plot(ts, vs, color="#444444", lw=0.6, zorder=2)
    ax.axhline(horizon, color="#888888", ls=":", lw=1)
    ax.text(0, horizon, " horizon", va="bottom", ha="left", fontsize=8, color="#666666")
    ax.set_xlim(0, max(duration, 1e-3))
    ax.set_ylim(-0.05 * horizon, horizon * 1.1)
    ax.set_xlabel("bag time (s)")
    ax.set_ylabel("time to contact (s)")
    ax.set_title("Smallest time to contact over the scene, per cycle")
    handles = level_legend() + [Patch(color=DEGRADED_COLOUR, alpha=0.35, label="DEGRADED")]
    ax.legend(handles=handles, loc="upper right", fontsize=8, ncol=4)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return png(fig, path)


def speed_scale_plot(cycles, duration, intervals, path):
    """Speed and separation monitoring: the speed scale per cycle and the rule's raw scale."""
    fig, ax = plt.subplots(figsize=(11, 2.6))
    shade_degraded(ax, intervals)
    ts = [c["t"] for c in cycles]
    ax.plot(ts, [c["raw_scale"] if c["raw_scale"] is not None else math.nan for c in cycles],
            color="#888888", ls=":", lw=1.0, label="raw scale (the rule)")
    ax.plot(ts, [c["speed_scale"] if c["speed_scale"] is not None else math.nan for c in cycles],
            color="#1d3557", lw=1.3, label="speed scale (after the DEGRADED cap and hysteresis)")
    ax.set_xlim(0, max(duration, 1e-3))
    ax.set_ylim(-0.05, 1.1)
    ax.set_xlabel("bag time (s)")
    ax.set_ylabel("scale")
    ax.set_title("Speed and separation monitoring, per cycle")
    handles, _ = ax.get_legend_handles_labels()
    handles.append(Patch(color=DEGRADED_COLOUR, alpha=0.35, label="DEGRADED"))
    ax.legend(handles=handles, loc="lower right", fontsize=8, ncol=3)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return png(fig, path)


def timelines_plot(pairs, events_by_pair, eps_by_pair, horizon, duration, intervals, path):
    """One row per pair: time to contact (points, level colours) and distance (dashed line)."""
    n = len(pairs)
    fig, axes = plt.subplots(n, 1, figsize=(11, 1.45 * n + 0.9), sharex=True, squeeze=False)
    max_dist = max([e.distance for p in pairs for e in events_by_pair[p] if e.state != "END"] + [0.1])
    for ax, pair in zip(axes[:, 0], pairs):
        shade_degraded(ax, intervals)
        for ep in eps_by_pair[pair]:
            end = ep.end if ep.end is not None else duration
            ax.axvspan(ep.start, end, color=COLOURS[ep.peak_level], alpha=0.12, lw=0)
        live = [e for e in events_by_pair[pair] if e.state != "END"]
        for level in replay_data.LEVELS:
            pts = [(e.t, e.time_to_contact) for e in live if e.level == level]
            if pts:
                ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=5, color=COLOURS[level], zorder=3)
        ax.set_ylim(-0.05 * horizon, horizon * 1.1)
        ax.set_ylabel("ttc (s)", fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.3)
        ax.text(0.005, 0.93, "%s <-> %s" % pair, transform=ax.transAxes, fontsize=9,
                va="top", ha="left", weight="bold")
        ax2 = ax.twinx()
        # Distance, broken between episodes.
        ts, ds, last_t = [], [], None
        for e in live:
            if last_t is not None and e.t - last_t > 0.2:
                ts.append(math.nan)
                ds.append(math.nan)
            ts.append(e.t)
            ds.append(e.distance)
            last_t = e.t
        ax2.plot(ts, ds, color="#333333", ls="--", lw=0.9)
        ax2.set_ylim(0, max_dist * 1.1)
        ax2.set_ylabel("dist (m)", fontsize=8)
        ax2.tick_params(labelsize=8)
    axes[-1, 0].set_xlim(0, max(duration, 1e-3))
    axes[-1, 0].set_xlabel("bag time (s)")
    handles = level_legend() + [Line2D([], [], color="#333333", ls="--", label="distance (right axis)"),
                                Patch(color=DEGRADED_COLOUR, alpha=0.35, label="DEGRADED")]
    height = fig.get_figheight()
    fig.legend(handles=handles, loc="upper center", fontsize=8, ncol=5, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / height))
    return png(fig, path)


def fmt(v, unit=""):
    if v is None or (isinstance(v, float) and (math.isinf(v) or math.isnan(v))):
        return "–"
    return "%.2f%s" % (v, unit)


def table(headers, rows, classes=None):
    out = ["<table>"]
    if headers:
        out.append("<tr>%s</tr>" % "".join("<th>%s</th>" % html.escape(h) for h in headers))
    for i, r in enumerate(rows):
        cls = ' class="%s"' % classes[i] if classes and classes[i] else ""
        out.append("<tr%s>%s</tr>" % (cls, "".join("<td>%s</td>" % html.escape(str(c)) for c in r)))
    out.append("</table>")
    return "\n".join(out)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--max-pairs", type=int, default=40,
                    help="timelines for at most this many pairs (the most severe first)")
    args = ap.parse_args(argv)
    out = args.out_dir
    summary = replay_data.read_summary(out)
    cycles = list(replay_data.read_cycles(os.path.join(out, "cycles.csv")))
    events = list(replay_data.read_events(os.path.join(out, "events.csv")))
    duration = summary["bag_seconds"]
    horizon = summary.get("horizon", 2.0)
    eps = replay_data.episodes(events)
    intervals = replay_data.degraded_intervals(cycles)

    # Per cycle, its earliest predicted contact (the events are sorted: the first non-END).
    earliest = {}
    for e in events:
        if e.state != "END" and e.stamp not in earliest:
            earliest[e.stamp] = e
    events_by_pair, eps_by_pair = {}, {}
    for e in events:
        events_by_pair.setdefault(e.pair, []).append(e)
    for ep in eps:
        eps_by_pair.setdefault(ep.pair, []).append(ep)
    rank = replay_data.LEVEL_RANK
    pairs = sorted(eps_by_pair, key=lambda p: (-max(rank[ep.peak_level] for ep in eps_by_pair[p]),
                                               min(ep.min_ttc for ep in eps_by_pair[p]), p))
    shown = pairs[:args.max_pairs]

    images = [("Smallest time to contact", min_ttc_plot(
        cycles, earliest, horizon, duration, intervals, os.path.join(out, "min_ttc.png")))]
    ssm_cycles = [c for c in cycles if c.get("speed_scale") is not None]
    speed_image = (speed_scale_plot(cycles, duration, intervals, os.path.join(out, "speed_scale.png"))
                   if ssm_cycles else None)
    if shown:
        images.append(("Timelines", timelines_plot(
            shown, events_by_pair, eps_by_pair, horizon, duration, intervals,
            os.path.join(out, "timelines.png"))))

    drops = [(k, v) for k, v in summary["drops"].items() if v]
    summary_rows = [
        ("bag", "%s (%.2f s)" % (summary["bag"], duration)),
        ("configuration", ", ".join(summary["config_files"]) or "(the node's defaults)"),
        ("URDF", summary["urdf"] or "(none)"),
        ("config fingerprint", summary.get("config_fingerprint", "(not recorded)")),
        ("prediction", "%s Hz, horizon %s s, fixed frame %s" % (
            summary.get("rate"), summary.get("horizon"), summary.get("fixed_frame"))),
        ("input", "%d arrays on %s; %d tf + %d tf_static messages" % (
            summary["arrays"], ", ".join(summary.get("input_topics", [])),
            summary["tf_messages"], summary["tf_static_messages"])),
        ("cycles", "%d, of which %d DEGRADED" % (summary["cycles"], summary["degraded_cycles"])),
        ("tracks", "%d distinct, at most %d at once; %d robot bodies" % (
            summary["distinct_tracks"], summary["max_tracks"], len(summary.get("robot_bodies", [])))),
        ("events", "%d BEGIN, %d ONGOING, %d END; %d episodes over %d pairs" % (
            summary["events"]["BEGIN"], summary["events"]["ONGOING"], summary["events"]["END"],
            len(eps), len(eps_by_pair))),
        ("dropped", ", ".join("%s %d" % kv for kv in drops) if drops else "nothing"),
        ("clock went back", str(summary["resets"])),
        ("replay", "%.3f s of wall time (%.0fx real time)" % (
            summary["wall_seconds"], summary["speed_factor"])),
    ]
    if ssm_cycles:
        stops = replay_data.protective_stops(cycles)
        stopped = sum(((end if end is not None else duration) - start) for start, end in stops)
        limiting = {}
        for c in ssm_cycles:
            if c["raw_scale"] is not None and c["raw_scale"] < 1.0 and c.get("ssm_object"):
                limiting[c["ssm_object"]] = limiting.get(c["ssm_object"], 0) + 1
        summary_rows.append(("speed scale", "minimum %.2f, mean %.2f; %d protective stops (%.2f s at 0)%s" % (
            min(c["speed_scale"] for c in ssm_cycles),
            sum(c["speed_scale"] for c in ssm_cycles) / len(ssm_cycles), len(stops), stopped,
            ("; limited by " + ", ".join("%s (%d cycles)" % kv for kv in
                                        sorted(limiting.items(), key=lambda kv: -kv[1])))
            if limiting else "")))
    for g in summary.get("skipped_gaps", []):
        summary_rows.append(("gap", "no input from %.3f s to %.3f s: %d cycles skipped" % (
            g["from"], g["to"], g["cycles"])))
    for m in summary["missing_frames"]:
        summary_rows.append(("MISSING", m))
    for w in summary["warnings"]:
        summary_rows.append(("warning", w))

    ep_rows, ep_classes = [], []
    for ep in eps:
        ep_rows.append(("%s <-> %s" % ep.pair, "%s / %s" % ep.labels, "%.3f" % ep.start,
                        "open" if ep.end is None else "%.3f" % ep.end, "%.2f" % ep.duration(duration),
                        ep.peak_level, fmt(ep.min_ttc, " s"), fmt(ep.min_distance, " m"),
                        "yes" if ep.stale else ""))
        ep_classes.append(ep.peak_level.lower())

    parts = ["""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>Replay of %s</title>
<style>
body { font-family: sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: left; }
th { background: #f0f0f0; }
tr.warning td { background: #fdf0e3; } tr.critical td { background: #f9dcdc; }
img { max-width: 100%%; border: 1px solid #ddd; }
</style></head><body>
<h1>Replay of %s</h1>""" % (html.escape(os.path.basename(summary["bag"])), html.escape(summary["bag"]))]
    parts.append("<h2>Summary</h2>")
    parts.append(table(None, summary_rows))
    parts.append("<h2>DEGRADED intervals</h2>")
    if intervals:
        parts.append(table(("start (s)", "end (s)", "reasons"),
                           [("%.3f" % a, "%.3f" % b, "; ".join(r) or "(no detail)") for a, b, r in intervals]))
    else:
        parts.append("<p>None: every cycle was OK.</p>")
    parts.append("<h2>Smallest time to contact</h2>")
    parts.append('<img alt="smallest time to contact per cycle" src="data:image/png;base64,%s">'
                 % base64.b64encode(images[0][1]).decode())
    if speed_image is not None:
        parts.append("<h2>Speed scale</h2><p>Speed and separation monitoring (ISO/TS 15066): the "
                     "scale a controller would apply, and the rule's raw scale.</p>")
        parts.append('<img alt="speed scale per cycle" src="data:image/png;base64,%s">'
                     % base64.b64encode(speed_image).decode())
    parts.append("<h2>Episodes</h2><p>From a pair's BEGIN to its END; times in seconds after the "
                 "bag's first message.</p>")
    parts.append(table(("pair", "labels", "start", "end", "duration", "peak level",
                        "min time to contact", "min distance", "stale"), ep_rows, ep_classes)
                 if ep_rows else "<p>No contact was predicted.</p>")
    if len(images) > 1:
        parts.append("<h2>Timelines per pair</h2>")
        if len(pairs) > len(shown):
            parts.append("<p>The %d most severe of %d pairs (--max-pairs).</p>" % (len(shown), len(pairs)))
        parts.append('<img alt="timelines per pair" src="data:image/png;base64,%s">'
                     % base64.b64encode(images[1][1]).decode())
    parts.append("</body></html>\n")
    page = os.path.join(out, "report.html")
    with open(page, "w") as f:
        f.write("\n".join(parts))

    print("episodes (%d):" % len(eps))
    for ep in eps:
        print("  %-34s %8.3f - %-8s %-8s min ttc %-7s min dist %s" % (
            "%s <-> %s" % ep.pair, ep.start, "open" if ep.end is None else "%.3f" % ep.end,
            ep.peak_level, fmt(ep.min_ttc, " s"), fmt(ep.min_distance, " m")))
    for a, b, r in intervals:
        print("  DEGRADED %.3f - %.3f: %s" % (a, b, "; ".join(r)))
    print("  report: %s" % page)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
