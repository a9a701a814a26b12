#!/usr/bin/env python3
"""The md5s in foreign_msgs/md5s.txt, recomputed from the stored definitions with ROS's own
algorithm (genmsg.compute_md5, as gencpp and genpy run it), and the md5s of the standard types
they nest checked against the headers Debian generated from its own packages.

Usage: test_foreign_md5s.py <foreign_msgs folder>. Exits non-zero on any mismatch.
"""

import os
import re
import sys
import unittest

import genmsg
import genmsg.gentools
import genmsg.msg_loader

FOREIGN = os.path.abspath(sys.argv.pop(1) if len(sys.argv) > 1 else
                          os.path.join(os.path.dirname(__file__), '..', '..', 'foreign_msgs'))
DEBIAN_PACKAGES = ['std_msgs', 'geometry_msgs', 'sensor_msgs', 'shape_msgs', 'visualization_msgs']


def read_table():
    """Rows of md5s.txt as dicts (type, version, md5, dir, upstream, commit, path)."""
    rows = []
    with open(os.path.join(FOREIGN, 'md5s.txt')) as table:
        for line in table:
            if not line.strip() or line.startswith('#'):
                continue
            cells = line.split()
            rows.append(dict(zip(['type', 'version', 'md5', 'dir', 'upstream', 'commit', 'path'],
                                 cells)))
    return rows


def search_path(package, version_dir):
    """genmsg's search path: Debian's standard packages, every stored foreign package, and for
    a version kept in a subfolder that subfolder first (genmsg takes the first file found)."""
    path = {p: ['/usr/share/%s/msg' % p] for p in DEBIAN_PACKAGES}
    for p in os.listdir(FOREIGN):
        if os.path.isdir(os.path.join(FOREIGN, p)):
            path[p] = [os.path.join(FOREIGN, p)]
    if version_dir not in ('.', None) and not version_dir.startswith('/'):
        path[package] = [os.path.join(FOREIGN, package, version_dir)] + path[package]
    return path


def compute_md5(msg_type, version_dir):
    context = genmsg.msg_loader.MsgContext.create_default()
    path = search_path(msg_type.split('/')[0], version_dir)
    spec = genmsg.msg_loader.load_msg_by_type(context, msg_type, path)
    genmsg.msg_loader.load_depends(context, spec, path)
    return genmsg.gentools.compute_md5(context, spec)


def debian_header_md5(msg_type):
    """The MD5Sum gencpp wrote into Debian's /usr/include/<package>/<Type>.h."""
    package, name = msg_type.split('/')
    with open('/usr/include/%s/%s.h' % (package, name)) as header:
        text = header.read()
    found = re.search(r'struct MD5Sum< ::%s::%s_<ContainerAllocator> >\s*\{\s*static const char\* '
                      r'value\(\)\s*\{\s*return "([0-9a-f]{32})"' % (package, name), text)
    return found.group(1) if found else None


class ForeignMd5s(unittest.TestCase):

    def setUp(self):
        self.rows = read_table()

    def test_table_lists_every_stored_definition(self):
        # Every .msg file under foreign_msgs/ has its row (and so its md5 and source).
        listed = set()
        for row in self.rows:
            if row['version'] == 'debian':
                continue
            package, name = row['type'].split('/')
            listed.add(os.path.normpath(os.path.join(package, row['dir'], name + '.msg')))
        stored = set()
        for root, _, files in os.walk(FOREIGN):
            for f in files:
                if f.endswith('.msg'):
                    stored.add(os.path.relpath(os.path.join(root, f), FOREIGN))
        self.assertEqual(stored, listed)

    def test_foreign_md5s_match_their_definitions(self):
        for row in self.rows:
            if row['version'] == 'debian':
                continue
            with self.subTest(type=row['type'], version=row['version']):
                self.assertEqual(compute_md5(row['type'], row['dir']), row['md5'])
                self.assertRegex(row['commit'], r'^[0-9a-f]{40}$')

    def test_versions_of_one_type_differ(self):
        # Each listed wire version is a distinct layout (else it would not need its own row).
        seen = {}
        for row in self.rows:
            key = (row['type'], row['md5'])
            self.assertNotIn(key, seen, 'duplicate version of %s' % row['type'])
            seen[key] = row['version']

    def test_debian_types_match_generated_headers(self):
        # The nested standard types come from Debian: their md5s as genmsg computes them from
        # /usr/share/<package>/msg, as the table states, and as Debian's gencpp output states.
        debian = [row for row in self.rows if row['version'] == 'debian']
        self.assertGreater(len(debian), 10)
        for row in debian:
            with self.subTest(type=row['type']):
                self.assertEqual(compute_md5(row['type'], None), row['md5'])
                self.assertEqual(debian_header_md5(row['type']), row['md5'])

    def test_pedsim_copies_spencer(self):
        # pedsim_msgs/TrackedPersons is a copy of spencer's: same layouts, same md5s.
        md5s = {(r['type'].split('/')[0], r['version']): r['md5'] for r in self.rows
                if r['type'].endswith('/TrackedPersons')}
        for version in ('v1', 'v2'):
            self.assertEqual(md5s[('pedsim_msgs', version)],
                             md5s[('spencer_tracking_msgs', version)])


if __name__ == '__main__':
    unittest.main()
