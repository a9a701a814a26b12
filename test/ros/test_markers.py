#!/usr/bin/env python3
"""Markers consistent with bodies and events.

Bodies: robot body "column" (0.4 x 0.4 x 2 m, centre (0, 0, 1) via a static tf world ->
base_link and its offset), "walker" (0.5 m cube approaching the column along +x at 0.5 m/s,
gap 2 m: one active event for the whole run, time to contact 4 -> 2 s, horizon 5 s) and
"crate" (1 m cube at rest at (5, 5, 0.5), no event). Over 2 s of MarkerArrays:
- only the namespaces bodies, swept, nearest, ttc_text, velocity, ids, status; frame_id =
  fixed frame;
- every added marker has lifetime = ~marker_lifetime (0.7 s, > 0);
- "bodies": one marker per body (3) in every array, each body keeping its marker id, placed at
  the body's centre (CUBE markers: scaled to the body's size);
- "nearest" and "ttc_text": exactly one added marker each per array (one active event); the
  nearest line joins the event's nearest points; the text names the pair and its time to
  contact ("column - walker 3.21 s");
- "ids": one text per body, its id, above the body; "status": one text, "OK | earliest: column -
  walker in ... s (...)" while the scene is fresh.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from visualization_msgs.msg import Marker  # noqa: E402

from wp_node_testlib import (MARKER_NAMESPACES, ScenePublisher, StaticBody, Track,  # noqa: E402
                             broadcast_static, check_array_basics, connected_collector, events_for,
                             pt, vnorm, vsub)

LIFETIME = 0.7


class MarkersTest(unittest.TestCase):
    def test_markers(self):
        tf_pub = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        col = connected_collector(self)
        column = StaticBody("column", "robot", (0.0, 0.0, 1.0), (0.2, 0.2, 1.0))
        walker = Track("walker", "default", (-2.45, 0.0, 1.0), (0.5, 0.5, 0.5), (0.5, 0.0, 0.0))
        crate = Track("crate", "default", (5.0, 5.0, 0.5), (1, 1, 1))
        scene = ScenePublisher("tracked_objects", [walker, crate], latency=0.05)
        t0 = scene.start()
        rospy.sleep(0.6)
        start = rospy.Time.now()
        rospy.sleep(3.0)  # the walker's gap closes from 1.7 m to 0.2 m
        scene.stop()
        arrays = [a for t, a in col.markers if t >= start and t <= start + rospy.Duration(3.0)]
        contacts = dict((m.header.stamp, m) for m in col.contact_msgs(since=t0))
        for m in contacts.values():
            check_array_basics(self, m)
        self.assertGreaterEqual(len(arrays), 20, "only %d MarkerArrays in 2 s" % len(arrays))

        bodies = [column, walker, crate]
        ids = {}
        lines_checked = 0
        ssm_checked = 0
        for arr in arrays:
            per_ns = {}
            stamp = None
            for mk in arr.markers:
                self.assertIn(mk.ns, MARKER_NAMESPACES, "unexpected namespace %r" % mk.ns)
                if mk.action != Marker.ADD:
                    continue
                self.assertEqual(mk.header.frame_id, "world", "%s/%d" % (mk.ns, mk.id))
                self.assertGreater(mk.lifetime.to_sec(), 0.0, "%s/%d lifetime" % (mk.ns, mk.id))
                self.assertAlmostEqual(mk.lifetime.to_sec(), LIFETIME, delta=1e-6,
                                       msg="%s/%d lifetime != marker_lifetime" % (mk.ns, mk.id))
                per_ns.setdefault(mk.ns, []).append(mk)
                if mk.header.stamp.to_sec() > 0:
                    stamp = mk.header.stamp
            if stamp is None:
                stamp = rospy.Time.now()

            # bodies: one each, at the body's centre, stable ids
            got = per_ns.get("bodies", [])
            self.assertEqual(len(got), 3, "bodies markers: %r" % [(m.id, pt(m.pose.position))
                                                                   for m in got])
            self.assertEqual(len(set(m.id for m in got)), 3, "body marker ids not distinct")
            for body in bodies:
                centre, _ = body.state(stamp)
                best = min(got, key=lambda m: vnorm(vsub(pt(m.pose.position), centre)))
                self.assertLess(vnorm(vsub(pt(best.pose.position), centre)), 0.06,
                                "no bodies marker at %s's centre %r" % (body.id, centre))
                if best.type == Marker.CUBE:
                    for k, s in enumerate((best.scale.x, best.scale.y, best.scale.z)):
                        self.assertAlmostEqual(s, 2 * body.half[k], delta=1e-3,
                                               msg="%s's CUBE marker scale" % body.id)
                prev = ids.setdefault(body.id, best.id)
                self.assertEqual(prev, best.id, "%s's body marker id changed" % body.id)

            # one active event -> one nearest line and one ttc text
            near = per_ns.get("nearest", [])
            text = per_ns.get("ttc_text", [])
            self.assertEqual(len(near), 1, "nearest markers: %d" % len(near))
            self.assertEqual(len(text), 1, "ttc_text markers: %d" % len(text))
            self.assertEqual(text[0].type, Marker.TEXT_VIEW_FACING)
            self.assertRegex(text[0].text, r"^column - walker [0-9]+\.[0-9]{2} s$",
                             "ttc text does not name the pair")
            label = dict((m.text, m) for m in per_ns.get("ids", []))
            self.assertEqual(set(label), {"column", "walker", "crate"}, "ids labels")
            for body in bodies:
                centre, _ = body.state(stamp)
                self.assertGreater(label[body.id].pose.position.z, centre[2] + body.half[2],
                                   "%s's id label not above it" % body.id)
            status = per_ns.get("status", [])
            self.assertEqual(len(status), 1, "status markers: %d" % len(status))
            self.assertRegex(status[0].text,
                             r"^OK \| earliest: column - walker in [0-9.]+ s \((NOTICE|WARNING|CRITICAL)\)"
                             r" \| speed scale [01]\.[0-9]{2}( \(STOP\))?$")
            # Speed and separation: once the walker (0.5 m/s straight at the column) is within
            # S_p(v_max) = 0.5 (0.1 + 0.3) + 1.0 (0.1 + 0.15) + 0.22 = 0.67 m of it, the column
            # grown by 0.67 m, the line between the nearest points and the scale's text.
            ssm = dict((m.id, m) for m in per_ns.get("ssm", []))
            wx, _ = walker.state(stamp)
            gap = -0.2 - (wx[0] + 0.25)
            if gap < 0.67 - 0.03:
                self.assertEqual(set(ssm), {0, 1, 2}, "ssm markers at gap %.3f m" % gap)
            if ssm:
                zone = ssm[0]
                self.assertEqual(zone.type, Marker.CUBE)
                self.assertLess(vnorm(vsub(pt(zone.pose.position), column.centre)), 1e-6)
                for k, s in enumerate((zone.scale.x, zone.scale.y, zone.scale.z)):
                    self.assertAlmostEqual(s, 2 * (column.half[k] + 0.67), delta=1e-3,
                                           msg="ssm zone scale")
                self.assertLess(zone.color.a, 0.5, "the zone is translucent")
                self.assertEqual(ssm[1].type, Marker.LINE_LIST)
                self.assertAlmostEqual(ssm[1].points[1].x, -0.2, delta=1e-6)
                self.assertRegex(ssm[2].text,
                                 r"^scale [01]\.[0-9]{2}( \((DEGRADED|rising to [01]\.[0-9]{2})\))?: "
                                 r"walker [0-9.]+ m (<|>=) S_p 0\.67 m$")
                # At or beyond S_p the pair allows full speed: a lower scale must say why.
                shown = float(ssm[2].text.split()[1].rstrip(":"))
                if ">=" in ssm[2].text and shown < 1.0:
                    self.assertRegex(ssm[2].text, r"\((DEGRADED|rising to 1\.00)\)")
                ssm_checked += 1
            line = near[0]
            if len(line.points) >= 2:
                ends = sorted([pt(line.points[0]), pt(line.points[-1])])
                ev_msg = contacts.get(line.header.stamp)
                if ev_msg is not None and events_for(ev_msg, "column", "walker"):
                    ev = events_for(ev_msg, "column", "walker")[0]
                    want = sorted([pt(ev.point_a), pt(ev.point_b)])
                    tol = 1e-4
                else:
                    wx, _ = walker.state(stamp)
                    want = sorted([(wx[0] + 0.25, 0.0, 1.0), (-0.2, 0.0, 1.0)])
                    tol = 0.06
                for e, w in zip(ends, want):
                    # x along the approach is determined; y, z only within the faces
                    self.assertAlmostEqual(e[0], w[0], delta=tol,
                                           msg="nearest line %r vs %r" % (ends, want))
                    self.assertLessEqual(abs(e[1]), 0.2 + tol)
                    self.assertLessEqual(abs(e[2] - 1.0), 0.25 + tol)
                lines_checked += 1
        self.assertGreater(lines_checked, 0, "no nearest line with points")
        self.assertGreater(ssm_checked, 0, "no speed and separation markers")
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_markers")
    rostest.rosrun("workspace_proximity", "test_markers", MarkersTest)
