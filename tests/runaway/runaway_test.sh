#!/usr/bin/env bash
# A shader that never ends (tests/runaway/runaway.json) against the frame timeout and the signals:
# render with --frame-timeout ends with exit 3 naming the pass, and writes nothing; SIGTERM and
# SIGINT end render and the viewer promptly while the device still runs the frame.
#   runaway_test.sh CAUSTICA SOURCE_DIR
set -u
caustica=$1
graph=$2/tests/runaway/runaway.json
DISPLAY_BASE=290 source "$2/tests/view/xvfb.sh"

"$caustica" render --graph "$graph" --size 64x64 --set keep_going=0 --out "$dir/ended.png" > "$dir/log" 2>&1 ||
  fail "the graph with a loop that ends did not render"

start=$SECONDS
"$caustica" render --graph "$graph" --size 64x64 --frame-timeout 2 --out "$dir/never.png" > "$dir/log" 2>&1
status=$?
[ "$status" = 3 ] || fail "a frame past --frame-timeout exited $status, not 3"
grep -q "pass 'endless_loop' was still running" "$dir/log" || fail "the message does not name the pass"
[ $((SECONDS - start)) -lt 30 ] || fail "the timeout of 2 s took $((SECONDS - start)) s"
[ ! -e "$dir/never.png" ] || fail "a frame that did not finish wrote its picture"

# $1: the signal; $2: the exit code expected; the rest: the command. The signal comes once the
# command has been in its frame for 2 s (the default timeout is minutes); it must end within 5 s.
ends_on_signal() {
  local signal=$1 expected=$2
  shift 2
  "$@" > "$dir/log" 2>&1 &
  view_pid=$!
  sleep 3
  kill -0 "$view_pid" 2>/dev/null || fail "$* ended before the signal"
  kill "-$signal" "$view_pid"
  for _ in $(seq 50); do kill -0 "$view_pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$view_pid" 2>/dev/null; then
    kill -9 "$view_pid"
    fail "$* still ran 5 s after SIG$signal"
  fi
  wait "$view_pid"
  local status=$?
  view_pid=""
  [ "$status" = "$expected" ] || fail "$* exited $status after SIG$signal, not $expected"
}
ends_on_signal TERM 143 "$caustica" render --graph "$graph" --size 64x64 --out "$dir/never.png"
ends_on_signal INT 130 "$caustica" render --graph "$graph" --size 64x64 --out "$dir/never.png"
ends_on_signal TERM 143 "$caustica" view --graph "$graph" --size 64x64
echo "runaway_test: passed"
