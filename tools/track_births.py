#!/usr/bin/env python3
"""Counts the tracks cloud_tracker starts (new ids on perceived_objects), per second, in three
phases of equal length: both sensors, the camera alone (scanner paused), the scanner alone
(camera paused). The sensors are paused through sensor_simulator's ~pause_camera and
~pause_scanner. Run beside `scripts/demo sensors:=true` on the same master (issue 23, demo2).

    /usr/bin/python3 tools/track_births.py [phase seconds, default 15]  (a development tool, not installed)
"""
import sys

import numpy as np

import rospy
from std_msgs.msg import Bool, Float64
from workspace_proximity.msg import PerceptionStatus, TrackedBoxArray


def steady(seconds):
    seen, born, shares, degraded, scales = set(), [0], [], [], []

    def on_objects(msg):
        for b in msg.boxes:
            if b.label != 'unseen' and b.id not in seen:
                seen.add(b.id)
                born[0] += 1

    rospy.Subscriber('/perceived_objects', TrackedBoxArray, on_objects, queue_size=50)
    rospy.Subscriber('/perception_status', PerceptionStatus,
                     lambda m: (shares.append(m.unseen_share), degraded.append(m.degraded)), queue_size=50)
    rospy.Subscriber('/speed_scale', Float64, lambda m: scales.append(m.data), queue_size=200)
    while not rospy.is_shutdown() and not shares:
        rospy.sleep(0.2)
    rospy.sleep(3.0)
    born[0], shares[:], degraded[:], scales[:] = 0, [], [], []
    rospy.sleep(seconds)
    s, sc = np.array(shares), np.array(scales)
    print('both sensors, %.0f s: %.1f tracks started/s; unseen share median %.3f p90 %.3f max %.3f '
          '(%d samples); perception DEGRADED %.0f %% of the time; speed_scale mean %.2f, 0 for %.0f %%' % (
              seconds, born[0] / seconds, np.median(s), np.percentile(s, 90), s.max(), len(s),
              100.0 * np.mean(degraded), sc.mean(), 100.0 * np.mean(sc == 0.0)), flush=True)


def main():
    rospy.init_node('track_births', anonymous=True)
    if len(sys.argv) > 1 and sys.argv[1] == '--steady':
        steady(float(sys.argv[2]) if len(sys.argv) > 2 else 30.0)
        return
    phase = float(sys.argv[1]) if len(sys.argv) > 1 else 15.0
    seen, counts = set(), {'born': 0, 'arrays': 0, 'boxes': 0}

    def on_objects(msg):
        counts['arrays'] += 1
        counts['boxes'] += len(msg.boxes)
        for b in msg.boxes:
            if b.label != 'unseen' and b.id not in seen:
                seen.add(b.id)
                counts['born'] += 1

    pause_cam = rospy.Publisher('/sensor_simulator/pause_camera', Bool, queue_size=1, latch=True)
    pause_scan = rospy.Publisher('/sensor_simulator/pause_scanner', Bool, queue_size=1, latch=True)
    rospy.Subscriber('/perceived_objects', TrackedBoxArray, on_objects, queue_size=50)
    # Wait for the first tracks (the demo starting up).
    while not rospy.is_shutdown() and counts['arrays'] == 0:
        rospy.sleep(0.2)
    rospy.sleep(3.0)
    for name, cam_paused, scan_paused in (('both sensors', False, False),
                                          ('camera only', False, True),
                                          ('scanner only', True, False)):
        pause_cam.publish(Bool(cam_paused))
        pause_scan.publish(Bool(scan_paused))
        rospy.sleep(1.0)  # the switch settles
        for k in counts:
            counts[k] = 0
        rospy.sleep(phase)
        print('%-13s %5.1f tracks started/s, %5.1f arrays/s, %4.1f boxes per array' % (
            name, counts['born'] / phase, counts['arrays'] / phase,
            counts['boxes'] / max(1, counts['arrays'])), flush=True)
    pause_cam.publish(Bool(False))
    pause_scan.publish(Bool(False))


if __name__ == '__main__':
    main()
