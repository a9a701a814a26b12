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
