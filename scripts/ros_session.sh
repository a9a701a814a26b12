# Sourced by scripts that need a ROS master of their own: a temporary ROS_HOME, a free port,
# the build's devel environment, and cleanup of everything started on exit.
ros_session_start() {
  ROS_HOME="$(mktemp -d /tmp/wp_ros_home.XXXXXX)"
  export ROS_HOME ROS_LOG_DIR="${ROS_HOME}/log"
  local port
  port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  export ROS_MASTER_URI="http://127.0.0.1:${port}" ROS_IP=127.0.0.1
  set +u
  # shellcheck disable=SC1091
  source "${WP_BUILD}/devel/setup.bash"
  set -u
  roscore -p "${port}" >"${ROS_HOME}/roscore.log" 2>&1 &
  WP_ROSCORE_PID=$!
  trap ros_session_stop EXIT
  for _ in $(seq 1 100); do
    rostopic list >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  echo "could not start roscore (see ${ROS_HOME}/roscore.log)" >&2
  return 1
}

ros_session_stop() {
  # Stop every child (monitor, generators) and the master, then remove the temporary home.
  pkill -INT -P $$ 2>/dev/null || true
  sleep 0.5
  pkill -KILL -P $$ 2>/dev/null || true
  [ -n "${WP_ROSCORE_PID:-}" ] && kill -INT "${WP_ROSCORE_PID}" 2>/dev/null || true
  wait 2>/dev/null || true
  [ -n "${WP_KEEP_ROS_HOME:-}" ] && return 0
  rm -rf "${ROS_HOME}"
}

# ros_nodelet_pair LOG SECONDS HOOK MONITOR_ARGS... -- LOAD_ARGS...
# Runs the proximity monitor and the load generator as nodelets in one manager (arrays,
# speed_scale and contacts pass as pointers: no serialisation, no socket, no poll thread),
# until the generator's summary line is in LOG (the manager's output, which holds both nodes'
# prints) or SECONDS + 20 s have passed, then stops them. HOOK (a function name, or "") is
# called with "start" once the monitor is loaded, just before the generator is, and with "end"
# as soon as the summary is there; WP_MANAGER_PID is the manager's pid meanwhile (bench-node
# reads the manager's CPU time there).
ros_nodelet_pair() {
  local log="$1" seconds="$2" hook="$3"
  shift 3
  local monitor_args=() load_args=()
  while [ $# -gt 0 ] && [ "$1" != "--" ]; do monitor_args+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  load_args=("$@")
  /usr/lib/nodelet/nodelet manager __name:=bench_manager >"${log}" 2>&1 &
  WP_MANAGER_PID=$!
  sleep 1
  /usr/lib/nodelet/nodelet load workspace_proximity/ProximityMonitorNodelet bench_manager \
    __name:=proximity_monitor "${monitor_args[@]}" >/dev/null 2>&1 &
  local loaders=($!)
  sleep 2
  [ -n "${hook}" ] && "${hook}" start
  /usr/lib/nodelet/nodelet load workspace_proximity/LoadGeneratorNodelet bench_manager \
    __name:=load_generator "${load_args[@]}" >/dev/null 2>&1 &
  loaders+=($!)
  local _
  for _ in $(seq 1 $(( seconds * 10 + 200 ))); do
    grep -q '^summary' "${log}" && break
    sleep 0.1
  done
  [ -n "${hook}" ] && "${hook}" end
  kill -INT "${loaders[@]}" 2>/dev/null || true
  sleep 1
  kill -INT "${WP_MANAGER_PID}"; wait "${WP_MANAGER_PID}" 2>/dev/null || true
  kill -KILL "${loaders[@]}" 2>/dev/null || true
}
