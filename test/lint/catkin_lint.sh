#!/usr/bin/env bash
# catkin_lint -W1 on the package must report nothing but the explicit exceptions below.
# Run by ctest (test catkin_lint); usage: test/lint/catkin_lint.sh PACKAGE_DIR
set -uo pipefail
export PATH="/usr/bin:/bin:${PATH}"
pkg="${1:?package directory}"
out="$(catkin_lint -W1 "${pkg}" 2>/dev/null)"
status=$?
# Exceptions, each a full line pattern:
# - scripts/ holds the developer's entry points (setup, build, test, demo, bench, ...), run from
#   the source tree and never installed; the installed executables are the node, the nodelets'
#   libraries, the demo nodes and the tools installed by CMakeLists.txt.
allowed='^workspace_proximity: warning: file '"'"'scripts/[A-Za-z0-9_.-]+'"'"' is executable but not installed$'
unexpected="$(printf '%s\n' "${out}" | grep -v -E "${allowed}" | grep -v -E '^$' || true)"
if [ -n "${unexpected}" ]; then
  echo "catkin_lint -W1 reports problems (exit ${status}):"
  echo "${unexpected}"
  exit 1
fi
echo "catkin_lint -W1: clean but for $(printf '%s\n' "${out}" | grep -c -E "${allowed}") uninstalled developer scripts in scripts/"
