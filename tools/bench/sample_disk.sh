#!/usr/bin/env bash
# The most a folder takes on disk while a command runs (du every 50 ms), for the
# temporary-disk figures of docs/scaling.md section 5.
# Usage: sample_disk.sh FOLDER COMMAND...   (FOLDER is emptied first; the command's
# output goes to FOLDER.log)
set -uo pipefail
folder=$1
shift
mkdir -p "$folder"
rm -rf "${folder:?}"/*
"$@" > "$folder.log" 2>&1 &
pid=$!
most=0
while kill -0 "$pid" 2> /dev/null; do
  now=$(du -sm "$folder" 2> /dev/null | cut -f1)
  [ -n "$now" ] && [ "$now" -gt "$most" ] && most=$now
  sleep 0.05
done
wait "$pid"
rc=$?
echo "exit $rc, at most $most MiB in $folder"
exit "$rc"
