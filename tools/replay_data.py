"""The replay's results as data: events.csv, cycles.csv and summary.json read back, events
grouped into episodes, DEGRADED intervals, and the same rows built from live ContactEventArray
messages (so the live node and the offline replay are compared by one definition).

An episode is one pair's life in the prediction: from its BEGIN to its END (or to the end of
the data when it never ends), with the peak level and the smallest time to contact and
distance of its BEGIN and ONGOING events. A pair whose contact flickers has several episodes.

Columns are addressed by name (csv.DictReader), so columns added to the files later (the speed
scale of each cycle) change nothing here. No ROS import at module level: the report runs
without ROS.
"""
import csv
import json
import math
import os
import re

LEVELS = ("NOTICE", "WARNING", "CRITICAL")
LEVEL_RANK = {name: i for i, name in enumerate(LEVELS)}
STATES = ("BEGIN", "ONGOING", "END")


class Event(object):
    """One row of events.csv."""
    __slots__ = ("stamp", "t", "state", "id_a", "id_b", "label_a", "label_b", "time_to_contact",
                 "time_to_separation", "distance", "closing_speed", "level", "stale")

    def __init__(self, **kw):
        for k in self.__slots__:
            setattr(self, k, kw[k])

    @property
    def pair(self):
        return (self.id_a, self.id_b)


class Episode(object):
    def __init__(self, pair, labels, start, start_stamp):
        self.pair = pair              # (id_a, id_b)
        self.labels = labels          # (label_a, label_b)
        self.start = start            # t of the BEGIN, s since the bag's first message
        self.start_stamp = start_stamp
        self.end = None               # t of the END; None: still predicted when the data ends
        self.end_stamp = None
        self.peak_level = "NOTICE"
        self.peak_time = start        # t the peak level was first reached
        self.min_ttc = math.inf
        self.min_ttc_time = start
        self.min_distance = math.inf
        self.cycles = 0               # BEGIN + ONGOING events
        self.stale = False            # some event of it was stale

    @property
    def name(self):
        return "%s <-> %s" % self.pair

    def duration(self, data_end):
        return (self.end if self.end is not None else data_end) - self.start

    def __repr__(self):
        end = "open" if self.end is None else "%.3f" % self.end
        return "Episode(%s, %.3f-%s, %s)" % (self.name, self.start, end, self.peak_level)


def _float(text):
    return float(text)  # accepts "inf", "nan"


def read_events(path):
    """Every row of events.csv, in file order (cycle by cycle)."""
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            yield Event(stamp=float(row["stamp"]), t=float(row["t"]), state=row["state"],
                        id_a=row["id_a"], id_b=row["id_b"], label_a=row["label_a"],
                        label_b=row["label_b"], time_to_contact=_float(row["time_to_contact"]),
                        time_to_separation=_float(row["time_to_separation"]),
                        distance=_float(row["distance"]), closing_speed=_float(row["closing_speed"]),
                        level=row["level"], stale=row["stale"] == "1")


SSM_NUMBERS = ("speed_scale", "raw_scale", "separation", "required_separation", "approach_speed")


def read_cycles(path):
    """Every row of cycles.csv as a dict with typed stamp, t, status, events, tracks, details,
    and the speed and separation columns (numbers, or None when empty or absent)."""
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            row["stamp"] = float(row["stamp"])
            row["t"] = float(row["t"])
            row["events"] = int(row["events"])
            row["tracks"] = int(row["tracks"])
            row["details"] = [d for d in row["details"].split(" | ") if d] if row["details"] else []
            for key in SSM_NUMBERS:
                value = row.get(key)
                row[key] = float(value) if value not in (None, "") else None
            yield row


def protective_stops(cycles):
    """[(start t, end t or None)] of the stretches of cycles whose speed scale is 0."""
    stops, start = [], None
    for c in cycles:
        stopped = c.get("speed_scale") == 0.0
        if stopped and start is None:
            start = c["t"]
        elif not stopped and start is not None:
            stops.append((start, c["t"]))
            start = None
    if start is not None:
        stops.append((start, None))
    return stops


def read_summary(out_dir):
    with open(os.path.join(out_dir, "summary.json")) as f:
        return json.load(f)


def episodes(events, data_end=None):
    """Episodes from events in cycle order. Returns them sorted by start, then pair."""
    open_eps = {}
    done = []
    for e in events:
        ep = open_eps.get(e.pair)
        if e.state == "END":
            if ep is not None:
                ep.end, ep.end_stamp = e.t, e.stamp
                done.append(open_eps.pop(e.pair))
            continue
        if e.state == "BEGIN" and ep is not None:  # a BEGIN without END: close the old one
            ep.end, ep.end_stamp = e.t, e.stamp
            done.append(open_eps.pop(e.pair))
            ep = None
        if ep is None:  # BEGIN (or data starting mid-episode)
            ep = Episode(e.pair, (e.label_a, e.label_b), e.t, e.stamp)
            open_eps[e.pair] = ep
        ep.cycles += 1
        if LEVEL_RANK[e.level] > LEVEL_RANK[ep.peak_level]:
            ep.peak_level, ep.peak_time = e.level, e.t
        if e.time_to_contact < ep.min_ttc:
            ep.min_ttc, ep.min_ttc_time = e.time_to_contact, e.t
        ep.min_distance = min(ep.min_distance, e.distance)
        ep.stale = ep.stale or e.stale
    done.extend(open_eps.values())
    return sorted(done, key=lambda ep: (ep.start, ep.pair))


def _reason(line):
    """A DEGRADED line without its numbers, so one cause over many cycles is one reason."""
    return re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", "#", line)


def degraded_intervals(cycles):
    """[(start t, end t, [distinct reasons, first wording of each])] of consecutive DEGRADED
    cycles; end is the t of the first OK cycle after, or of the last cycle."""
    intervals = []
    current = None
    last_t = None
    for c in cycles:
        last_t = c["t"]
        if c["status"] == "DEGRADED":
            if current is None:
                current = [c["t"], None, {}]
            for d in c["details"]:
                current[2].setdefault(_reason(d), d)
        elif current is not None:
            current[1] = c["t"]
            intervals.append((current[0], current[1], list(current[2].values())))
            current = None
    if current is not None:
        intervals.append((current[0], last_t, list(current[2].values())))
    return intervals


def contact_rows(msg, bag_begin):
    """The events.csv rows (as Event) of one live ContactEventArray; `bag_begin` in s."""
    names = {0: "BEGIN", 1: "ONGOING", 2: "END"}
    stamp = msg.header.stamp.to_sec()
    for e in msg.events:
        yield Event(stamp=stamp, t=stamp - bag_begin, state=names[e.state], id_a=e.id_a,
                    id_b=e.id_b, label_a=e.label_a, label_b=e.label_b,
                    time_to_contact=e.time_to_contact, time_to_separation=e.time_to_separation,
                    distance=e.distance, closing_speed=e.closing_speed, level=LEVELS[e.level],
                    stale=bool(e.stale))


# ---- expected-episodes files (test/bags/*.episodes.csv) ----

def read_expected(path):
    """[(id_a, id_b, start, end or None, peak_level)] from a reviewed file ('#' comments)."""
    with open(path, newline="") as f:
        lines = [l for l in f if l.strip() and not l.lstrip().startswith("#")]
    out = []
    for row in csv.DictReader(lines):
        end = None if row["end"].strip() == "open" else float(row["end"])
        out.append((row["id_a"].strip(), row["id_b"].strip(), float(row["start"]), end,
                    row["peak_level"].strip()))
    return out


def write_expected(eps, f):
    f.write("id_a,id_b,start,end,peak_level\n")
    for ep in eps:
        end = "open" if ep.end is None else "%.3f" % ep.end
        f.write("%s,%s,%.3f,%s,%s\n" % (ep.pair[0], ep.pair[1], ep.start, end, ep.peak_level))


def _merge_gaps(episodes, gap):
    """One pair's episodes [(start, end or None, peak_level, ep)] in order, those apart by at
    most `gap` s joined (the later's end, the higher peak)."""
    merged = []
    for x in episodes:
        if merged and merged[-1][1] is not None and x[0] - merged[-1][1] <= gap:
            last = merged[-1]
            peak = x[2] if LEVEL_RANK[x[2]] > LEVEL_RANK[last[2]] else last[2]
            merged[-1] = (last[0], x[1], peak, last[3])
        else:
            merged.append(x)
    return merged


def compare_episodes(actual, expected, tolerance, merge_gap=0.0):
    """Differences between episodes `actual` ([Episode]) and `expected` ([(id_a, id_b, start,
    end or None, peak_level)]), per pair in order: the same number of episodes, each start and
    end within `tolerance` s (an open end matches an open end only), the same peak level.
    `merge_gap` > 0: on both sides, a pair's episodes apart by at most that many seconds count
    as one (a contact that grazes the threshold, missing from one cycle on one path only: the
    same as an end and a start each moved within the tolerance).
    Returns a list of readable differences (empty: they agree)."""
    problems = []
    by_pair_a, by_pair_e = {}, {}
    for ep in actual:
        by_pair_a.setdefault(ep.pair, []).append((ep.start, ep.end, ep.peak_level, ep))
    for x in expected:
        by_pair_e.setdefault((x[0], x[1]), []).append((x[2], x[3], x[4], x))
    if merge_gap > 0.0:
        by_pair_a = {k: _merge_gaps(v, merge_gap) for k, v in by_pair_a.items()}
        by_pair_e = {k: _merge_gaps(v, merge_gap) for k, v in by_pair_e.items()}
    for pair in sorted(set(by_pair_a) | set(by_pair_e)):
        a, e = by_pair_a.get(pair, []), by_pair_e.get(pair, [])
        show = lambda eps: ["%.3f-%s %s" % (x[0], "open" if x[1] is None else "%.3f" % x[1], x[2])
                            for x in eps]
        if len(a) != len(e):
            problems.append("%s <-> %s: %d episodes, expected %d (got %s; expected %s)" % (
                pair[0], pair[1], len(a), len(e), show(a), show(e)))
            continue
        for (start, end, peak, _), x in zip(a, e):
            where = "%s <-> %s episode expected at %.3f s" % (pair[0], pair[1], x[0])
            if abs(start - x[0]) > tolerance:
                problems.append("%s: starts at %.3f s (more than %.3f s off)" % (where, start, tolerance))
            if (end is None) != (x[1] is None):
                problems.append("%s: ends %s, expected %s" % (
                    where, "open" if end is None else "at %.3f s" % end,
                    "open" if x[1] is None else "at %.3f s" % x[1]))
            elif end is not None and abs(end - x[1]) > tolerance:
                problems.append("%s: ends at %.3f s, expected %.3f s (more than %.3f s off)" % (
                    where, end, x[1], tolerance))
            if peak != x[2]:
                problems.append("%s: peak %s, expected %s" % (where, peak, x[2]))
    return problems
