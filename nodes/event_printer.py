#!/usr/bin/env python3
"""Prints a readable live summary of the proximity monitor's contact events.

Subscribes to `contacts` (workspace_proximity/ContactEventArray) and prints
  * one line per BEGIN and END as they happen, and one when an ongoing contact's level rises
    (STALE marks a contact predicted from old data);
  * one line when the array's status changes between OK and DEGRADED, with its details;
  * once per ~summary_period seconds (default 1.0) a one-line summary: the number of active
    contacts, the earliest one and its level, or a warning when no array has arrived lately
    (the monitor publishes every cycle, so silence never means "all clear", and neither
    does an empty list while the status is DEGRADED);
  * from `safety_status` (speed and separation monitoring): a STOP line when the speed scale
    reaches 0 and a GO line when it rises again, and with each summary a "speed" line: the
    scale, the raw scale and the pair limiting it (or a warning when the scale is silent:
    a consumer must then act as if it were 0).
Parameters (private): ~summary_period (1.0 s), ~stale_after (1.0 s), ~color (auto: when a tty).
"""

import math
import sys
import threading

import rospy

from workspace_proximity.msg import ContactEvent, ContactEventArray, SafetyStatus

LEVELS = {ContactEvent.NOTICE: 'NOTICE', ContactEvent.WARNING: 'WARNING', ContactEvent.CRITICAL: 'CRITICAL'}
COLORS = {ContactEvent.NOTICE: '\033[36m', ContactEvent.WARNING: '\033[33m', ContactEvent.CRITICAL: '\033[1;31m'}
RESET = '\033[0m'


def level_name(level):
    return LEVELS.get(level, 'LEVEL%d' % level)


def stale_tag(ev):
    return '  STALE' if ev.stale else ''


def brief(details, keep=2):
    """The first few status details, each shortened, and how many more there are."""
    items = [d.strip() if len(d.strip()) <= 90 else d.strip()[:87] + '...' for d in details[:keep]]
    more = len(details) - keep
    return ('; '.join(items) or 'no details') + (' (+%d more)' % more if more > 0 else '')


def fmt_time(seconds):
    return 'inf' if math.isinf(seconds) else '%.2f s' % seconds


class Printer(object):
    def __init__(self, color):
        self.color = color
        self.lock = threading.Lock()
        self.active = {}        # (id_a, id_b) -> latest BEGIN/ONGOING event
        self.began = {}         # (id_a, id_b) -> header stamp of its BEGIN (s)
        self.earliest = None    # earliest active event of the latest array
        self.last_rx = None     # wall time of the latest array
        self.last_stamp = None
        self.frame = ''
        self.n_arrays = 0
        self.n_begin = 0
        self.n_end = 0
        self.worst = {}         # level -> count of contacts that reached it (by their peak)
        self.peak = {}          # (id_a, id_b) -> highest level seen while active
        self.anomalies = 0
        self.status = ContactEventArray.OK
        self.details = []
        self.safety = None      # latest SafetyStatus
        self.safety_rx = None   # wall time of its receipt
        self.stopped = None     # protective stop in force (None: no status yet)
        self.n_stops = 0

    def paint(self, text, level):
        return (COLORS.get(level, '') + text + RESET) if self.color else text

    def out(self, line):
        print(line, flush=True)

    def anomaly(self, text):
        self.anomalies += 1
        self.out('??     ' + text)

    def on_contacts(self, msg):
        stamp = msg.header.stamp.to_sec()
        with self.lock:
            self.n_arrays += 1
            self.last_rx = rospy.get_time()
            if self.last_stamp is not None and stamp < self.last_stamp:
                self.anomaly('contacts stamp went backwards (%.3f -> %.3f)' % (self.last_stamp, stamp))
            self.last_stamp = stamp
            self.frame = msg.header.frame_id
            # Details may change every cycle ("no data for 1.3 s", "1.4 s", ...): a line on a
            # change of status only; the summary shows the current details.
            if msg.status != self.status:
                if msg.status == ContactEventArray.OK:
                    self.out('STATUS OK: every source and robot link is fresh again')
                else:
                    self.out(self.paint('STATUS DEGRADED: ' + brief(msg.status_details), ContactEvent.WARNING))
            self.status, self.details = msg.status, list(msg.status_details)
            seen = set()
            for ev in msg.events:
                key = (ev.id_a, ev.id_b)
                pair = '%s <-> %s' % key
                if key in seen:
                    self.anomaly('pair %s appears twice in one array' % pair)
                seen.add(key)
                if ev.state == ContactEvent.BEGIN:
                    if key in self.active:
                        self.anomaly('BEGIN for %s, which is already active' % pair)
                    self.n_begin += 1
                    self.began[key] = stamp
                    self.peak[key] = ev.level
                    self.out(self.paint('BEGIN  %-28s in %s  dist %.2f m  %s%s'
                                        % (pair, fmt_time(ev.time_to_contact), ev.distance,
                                           level_name(ev.level), stale_tag(ev)), ev.level))
                    self.active[key] = ev
                elif ev.state == ContactEvent.ONGOING:
                    prev = self.active.get(key)
                    if prev is None:
                        if self.n_arrays == 1:  # started after its BEGIN: adopt it
                            self.out(self.paint('ACTIVE %-28s in %s  dist %.2f m  %s%s  (began before we listened)'
                                                % (pair, fmt_time(ev.time_to_contact), ev.distance,
                                                   level_name(ev.level), stale_tag(ev)), ev.level))
                        else:
                            self.anomaly('ONGOING for %s without a BEGIN' % pair)
                        self.began.setdefault(key, stamp)
                        self.peak.setdefault(key, ev.level)
                    elif ev.level > prev.level:
                        self.out(self.paint('RAISE  %-28s in %s  dist %.2f m  %s -> %s%s'
                                            % (pair, fmt_time(ev.time_to_contact), ev.distance,
                                               level_name(prev.level), level_name(ev.level),
                                               stale_tag(ev)), ev.level))
                    self.peak[key] = max(self.peak.get(key, ev.level), ev.level)
                    self.active[key] = ev
                elif ev.state == ContactEvent.END:
                    if key not in self.active:
                        if self.n_arrays > 1:
                            self.anomaly('END for %s, which is not active' % pair)
                        continue
                    del self.active[key]
                    self.n_end += 1
                    lasted = stamp - self.began.pop(key, stamp)
                    peak = self.peak.pop(key, ContactEvent.NOTICE)
                    self.worst[peak] = self.worst.get(peak, 0) + 1
                    self.out('END    %-28s after %.1f s  (peak %s)' % (pair, lasted, level_name(peak)))
                else:
                    self.anomaly('unknown state %d for %s' % (ev.state, pair))
            # A pair that silently disappeared (neither ONGOING nor END) is a protocol error.
            for key in [k for k in self.active if k not in seen]:
                self.anomaly('%s <-> %s vanished without an END' % key)
                del self.active[key]
                self.began.pop(key, None)
                self.peak.pop(key, None)
            live = [ev for ev in msg.events if ev.state != ContactEvent.END]
            self.earliest = min(live, key=lambda e: e.time_to_contact) if live else None

    def on_safety(self, msg):
        with self.lock:
            self.safety = msg
            self.safety_rx = rospy.get_time()
            if msg.protective_stop and self.stopped is not True:
                self.n_stops += 1
                self.out(self.paint('STOP   protective stop, speed scale 0: %s' % msg.reason,
                                    ContactEvent.CRITICAL))
            elif not msg.protective_stop and self.stopped:
                self.out('GO     speed scale %.3f and rising: %s' % (msg.speed_scale, msg.reason))
            self.stopped = msg.protective_stop

    def speed_line(self, now):
        """The speed scale's summary line, or None when the monitor never published one."""
        if self.safety_rx is None:
            return None
        age = now - self.safety_rx
        if age > self.stale_after:
            return self.paint('speed  NO SPEED SCALE for %.1f s: act as if it were 0' % age,
                              ContactEvent.CRITICAL)
        m = self.safety
        if m.id_object:
            pair = '%s -> %s %.2f m, S_p %.2f m (approach %.2f m/s)' % (
                m.id_object, m.id_robot, m.separation, m.required_separation, m.approach_speed)
        else:
            pair = 'no monitored object within reach'
        line = 'speed  scale %.2f (raw %.2f)  %s%s' % (
            m.speed_scale, m.raw_scale, pair,
            '  [DEGRADED]' if m.status == SafetyStatus.DEGRADED else '')
        level = (ContactEvent.CRITICAL if m.speed_scale <= 0.0 else
                 ContactEvent.WARNING if m.speed_scale < 1.0 else None)
        return self.paint(line, level) if level is not None else line

    def summary(self, _event=None):
        if rospy.is_shutdown():
            return
        with self.lock:
            now = rospy.get_time()
            if self.last_rx is None:
                self.out('----   no contacts received yet (is proximity_monitor running?)')
                return
            age = now - self.last_rx
            speed = self.speed_line(now)
            if age > self.stale_after:
                self.out(self.paint('----   NO DATA for %.1f s: the monitor is silent, state unknown' % age,
                                    ContactEvent.CRITICAL))
                if speed is not None:
                    self.out(speed)
                return
            n = len(self.active)
            counts = {}
            for ev in self.active.values():
                counts[ev.level] = counts.get(ev.level, 0) + 1
            degraded = self.status != ContactEventArray.OK
            note = '  [DEGRADED: %s]' % brief(self.details) if degraded else ''
            if n == 0:
                if degraded:
                    self.out(self.paint('----   0 active contacts, but NOT clear' + note, ContactEvent.WARNING))
                else:
                    self.out('----   0 active contacts  (clear)')
                if speed is not None:
                    self.out(speed)
                return
            e = self.earliest
            split = ', '.join('%d %s' % (counts[l], level_name(l).lower())
                              for l in sorted(counts, reverse=True))
            line = '----   %d active (%s)  earliest: %s <-> %s in %s  dist %.2f m  %s%s%s' % (
                n, split, e.id_a, e.id_b, fmt_time(e.time_to_contact), e.distance, level_name(e.level),
                stale_tag(e), note)
            self.out(self.paint(line, max(counts)))
            if speed is not None:
                self.out(speed)

    def final(self):
        with self.lock:
            peaks = ', '.join('%d %s' % (self.worst.get(l, 0), level_name(l).lower())
                              for l in (ContactEvent.CRITICAL, ContactEvent.WARNING, ContactEvent.NOTICE))
            self.out('event_printer: %d arrays, %d BEGIN, %d END (peak levels: %s), %d still active%s%s'
                     % (self.n_arrays, self.n_begin, self.n_end, peaks, len(self.active),
                        ', %d protective stops' % self.n_stops if self.safety_rx is not None else '',
                        ', %d anomalies' % self.anomalies if self.anomalies else ''))


def main():
    rospy.init_node('event_printer')
    period = float(rospy.get_param('~summary_period', 1.0))
    color = rospy.get_param('~color', 'auto')
    if color == 'auto':
        color = sys.stdout.isatty()
    elif isinstance(color, str):
        color = color.lower() in ('true', '1', 'yes')
    printer = Printer(bool(color))
    printer.stale_after = float(rospy.get_param('~stale_after', 1.0))
    rospy.Subscriber('contacts', ContactEventArray, printer.on_contacts, queue_size=50)
    rospy.Subscriber('safety_status', SafetyStatus, printer.on_safety, queue_size=50)
    if period > 0:
        rospy.Timer(rospy.Duration(period), printer.summary)
    rospy.on_shutdown(printer.final)
    rospy.loginfo('event_printer: listening on %s', rospy.resolve_name('contacts'))
    rospy.spin()
    return 0


if __name__ == '__main__':
    try:
        sys.exit(main())
    except (rospy.ROSInterruptException, KeyboardInterrupt):
        pass
