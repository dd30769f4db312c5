# Sourced by the window tests: a scratch folder, an Xvfb of their own, and cleanup of both and of
# the programs under test ($view_pid: one process id, or several apart by spaces) on exit. Sets
# dir, DISPLAY; defines fail.
dir=$(mktemp -d)
display=$(( ${DISPLAY_BASE:-90} + $$ % 100 ))
xvfb_pid=""
view_pid=""
cleanup() {
  # shellcheck disable=SC2086 # one word a process
  [ -n "$view_pid" ] && kill $view_pid 2>/dev/null || true
  [ -n "$xvfb_pid" ] && kill "$xvfb_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; [ -f "$dir/log" ] && sed "s/^/  log: /" "$dir/log" >&2; exit 1; }

Xvfb ":$display" -screen 0 1280x720x24 -nolisten tcp > "$dir/xvfb.log" 2>&1 &
xvfb_pid=$!
for _ in $(seq 100); do [ -e "/tmp/.X11-unix/X$display" ] && break; sleep 0.1; done
[ -e "/tmp/.X11-unix/X$display" ] || fail "Xvfb did not start: $(cat "$dir/xvfb.log")"
export DISPLAY=":$display"
