#!/usr/bin/env python3
"""Counts the tracks cloud_tracker starts (new ids on perceived_objects), per second, in three
phases of equal length: both sensors, the camera alone (scanner paused), the scanner alone
(camera paused). The sensors are paused through sensor_simulator's ~pause_camera and
~pause_scanner. Run beside `scripts/demo sensors:=true` on the same master (issue 23, demo2).

    tools/track_births.py [phase seconds, default 15]
"""
import sys

import rospy
from std_msgs.msg import Bool
from workspace_proximity.msg import TrackedBoxArray


def main():
    phase = float(sys.argv[1]) if len(sys.argv) > 1 else 15.0
    rospy.init_node('track_births', anonymous=True)
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
