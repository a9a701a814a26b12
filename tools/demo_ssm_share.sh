#!/usr/bin/env bash
# Runs the demo headless and tools/demo_ssm_share.py beside it on a master of its own, and
# prints the tool's report (issue 23, demo3). A development tool, not installed.
#   bash tools/demo_ssm_share.sh LABEL START LENGTH [roslaunch args, e.g. sensors:=true]
# Build first (scripts/build); WP_BUILD_DIR as for scripts/demo.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
label="$1" start="$2" length="$3"; shift 3
port="$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
export WP_ROS_PORT="${port}" ROS_MASTER_URI="http://localhost:${port}"
duration="$(/usr/bin/python3 -c "print(int(${start} + ${length} + 25))")"
"${root}/scripts/demo" --duration "${duration}" printer:=false monitor_output:=log "$@" >/tmp/demo_ssm_share.$$.log 2>&1 &
demo=$!
# The demo stops by itself after its duration; stop it sooner if this script fails.
trap 'kill -INT "${demo}" 2>/dev/null || true' EXIT
set +eu
# shellcheck disable=SC1091
source "${WP_BUILD_DIR:-${root}/build}/devel/setup.bash"
set -eu
export PATH="/usr/bin:/bin:${PATH}"
until /usr/bin/python3 -c 'import socket,sys; s=socket.socket(); s.settimeout(0.5); sys.exit(0 if s.connect_ex(("127.0.0.1", int(sys.argv[1]))) == 0 else 1)' "${port}"; do
  sleep 0.5
  kill -0 "${demo}" 2>/dev/null || { cat /tmp/demo_ssm_share.$$.log; exit 1; }
done
# WP_SHARE_BAG=FILE.bag: also record what the report reads, for a closer look offline.
if [ -n "${WP_SHARE_BAG:-}" ]; then
  rosbag record -q -O "${WP_SHARE_BAG}" /safety_status /perceived_objects /true_objects /tracked_objects \
    /perception_status __name:=demo_ssm_share_bag >/dev/null 2>&1 &
fi
# rospy drops arguments holding ":=" (remappings): the label must not have one.
/usr/bin/python3 "${root}/tools/demo_ssm_share.py" --label "${label//:=/=}" --start "${start}" --length "${length}"
if [ -n "${WP_SHARE_BAG:-}" ]; then rosnode kill /demo_ssm_share_bag >/dev/null 2>&1 || true; fi
wait "${demo}" || true
trap - EXIT
rm -f /tmp/demo_ssm_share.$$.log
