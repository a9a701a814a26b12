#!/usr/bin/env python3
"""Draws docs/growth_model.png: how far a tracked person can be from the constant-velocity
prediction s seconds after the measurement, with the person settings of
config/proximity_monitor.yaml, from the formula (docs/node.md, "Tracked objects within bounds"):

    margin + position_error + min(e s + a s^2 / 2, (v_max + |v|) s)

    python3 tools/plot_growth_model.py [OUT.png]
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MARGIN, POSITION_ERROR = 0.20, 0.05          # m
VELOCITY_ERROR, MAX_ACCEL, MAX_SPEED = 0.3, 4.0, 2.0  # m/s, m/s^2, m/s
HORIZON = 2.0                                # s


def growth(s, speed):
    return np.minimum(VELOCITY_ERROR * s + 0.5 * MAX_ACCEL * s * s, (MAX_SPEED + speed) * s)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "docs/growth_model.png"
    s = np.linspace(0.0, HORIZON, 401)
    base = MARGIN + POSITION_ERROR
    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=100)
    ax.plot(s, np.full_like(s, MARGIN), color="0.4", lw=2,
            label="constant velocity (margin %.2f m)" % MARGIN)
    ax.plot(s, base + growth(s, 0.0), color="tab:red", lw=2,
            label="standing person: cap (%.1f + 0) m/s × s" % MAX_SPEED)
    ax.plot(s, base + growth(s, 1.4), color="tab:purple", lw=2,
            label="person walking at 1.4 m/s: cap (%.1f + 1.4) m/s × s" % MAX_SPEED)
    ax.plot(s, base + VELOCITY_ERROR * s + 0.5 * MAX_ACCEL * s * s, color="tab:orange", ls="--",
            lw=1.2, label="e s + a s²/2, no speed cap")
    ax.set_xlim(0.0, HORIZON)
    ax.set_ylim(0.0, 7.5)
    ax.set_xlabel("s, seconds after the measurement")
    ax.set_ylabel("margin around the box, m")
    ax.set_title("person: position_error %.2f m, velocity_error %.1f m/s,\n"
                 "max_accel %.0f m/s², max_speed %.1f m/s" %
                 (POSITION_ERROR, VELOCITY_ERROR, MAX_ACCEL, MAX_SPEED), fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out)


if __name__ == "__main__":
    main()
