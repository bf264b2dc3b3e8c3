#!/bin/sh
# Runs a command under a private X server (Debian's xvfb-run), for the tests
# that draw with ParaView. xvfb-run -a takes the first display number without
# a lock file, so two test runs started together on one machine can pick the
# same one and one of them loses its server ("bad X server connection"): the
# search starts at a number drawn from this process's id, and a run that lost
# its server is tried again, up to five times. Any other failure is the
# command's own and is returned at once. A server can also be lost on a
# loaded machine (slow to start, or gone mid-run): a pause before each new try.
# usage: tests/io/headless.sh XVFB_RUN COMMAND [ARG ...]
xvfb_run=$1
shift
log=$(mktemp)
trap 'rm -f "$log"' EXIT
for attempt in 1 2 3 4 5; do
  "$xvfb_run" -a -n $((100 + ($$ * 7 + attempt * 131) % 800)) "$@" > "$log" 2>&1
  status=$?
  if [ $status -eq 0 ] || ! grep -q "bad X server connection\|Xvfb failed\|cannot open display" "$log"; then
    cat "$log"
    exit $status
  fi
  echo "headless.sh: attempt $attempt lost its X server; trying again" >&2
  sleep "$attempt"
done
cat "$log"
exit $status
