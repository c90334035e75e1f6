#!/usr/bin/env bash
# The output that cannot be written, and the staging folders of killed runs:
#   * a full disk (write_fault.so, LD_PRELOAD) at several points of a run, and a read-only file
#     system: exit 4, one line "chainmail: cannot write PATH: REASON", nothing left behind (no
#     destination, no staging folder, no parent folder the run created);
#   * a run killed with SIGKILL leaves its staging folder; the next run into the same destination
#     removes it, and keeps a look-alike folder without chainmail's marker.
# Usage: output_failures.sh CHAINMAIL WRITE_FAULT_SO SCENE
set -u
chainmail=$1 fault=$2 scene=$3
work=$(mktemp -d)
trap 'umount "$work/small" "$work/ro" 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
small=(--set weave.rows=6 --set weave.cols=6 --set duration=0.2 --backends plausible
       --reference none --cache none --quiet --frames)

leftovers() { find "$work/dest" -mindepth 1 2>/dev/null | head -3; }

# the bytes a whole run writes, then budgets that fail it early, midway and at its last file
rm -rf "$work/dest"; mkdir "$work/dest"
WRITE_FAULT_COUNT="$work/count" LD_PRELOAD=$fault \
  "$chainmail" run "$scene" "${small[@]}" --out "$work/dest/made/run" >/dev/null 2>&1 ||
  fail "the run without faults failed"
total=$(cat "$work/count")
[ "$total" -gt 10000 ] || fail "the run wrote only $total bytes"
for bytes in 0 200 $((total / 10)) $((total / 2)) $((total * 9 / 10)) $((total - 300)) \
             $((total - 40)); do
  for code in 28 30; do  # ENOSPC, EROFS
    rm -rf "$work/dest"; mkdir "$work/dest"
    WRITE_FAULT_BYTES=$bytes WRITE_FAULT_ERRNO=$code LD_PRELOAD=$fault \
      "$chainmail" run "$scene" "${small[@]}" --out "$work/dest/made/run" 2>"$work/err"
    status=$?
    reason=$([ "$code" = 28 ] && echo "No space left on device" || echo "Read-only file system")
    [ "$status" = 4 ] || fail "$bytes bytes, errno $code: exit $status, not 4: $(cat "$work/err")"
    [ "$(wc -l <"$work/err")" = 1 ] || fail "$bytes bytes: stderr is not one line: $(cat "$work/err")"
    grep -q "^chainmail: cannot write $work/dest/made/.*: $reason\$" "$work/err" ||
      fail "$bytes bytes, errno $code: message: $(cat "$work/err")"
    [ -z "$(leftovers)" ] || fail "$bytes bytes, errno $code: left behind: $(leftovers)"
  done
done
echo "full disk and read-only (fault injection): checked"

# the same on real file systems where this user may mount them (root): a 64 KiB tmpfs that fills
# up, and a read-only one
mkdir "$work/small" "$work/ro"
if mount -t tmpfs -o size=64k tmpfs "$work/small" 2>/dev/null; then
  mount -t tmpfs -o size=64k,ro tmpfs "$work/ro"
  "$chainmail" run "$scene" "${small[@]}" --set weave.rows=30 --set weave.cols=30 \
    --out "$work/small/made/run" 2>"$work/err"
  status=$?
  [ "$status" = 4 ] && grep -q "^chainmail: cannot write $work/small/made/.*: No space left on device\$" \
    "$work/err" || fail "64 KiB tmpfs: exit $status: $(cat "$work/err")"
  [ -z "$(ls -A "$work/small")" ] || fail "64 KiB tmpfs: left behind: $(ls -A "$work/small")"
  "$chainmail" run "$scene" "${small[@]}" --out "$work/ro/run" 2>"$work/err"
  status=$?
  [ "$status" = 4 ] && grep -q "^chainmail: cannot write $work/ro/run: Read-only file system\$" \
    "$work/err" || fail "read-only tmpfs: exit $status: $(cat "$work/err")"
  umount "$work/small" "$work/ro"
  echo "full and read-only tmpfs: checked"
else
  echo "no tmpfs can be mounted here: the real file systems are left out"
fi

# a run killed in the middle, then a run into the same destination
rm -rf "$work/dest"; mkdir "$work/dest"
"$chainmail" run "$scene" "${small[@]}" --set duration=100 --out "$work/dest/run" 2>/dev/null &
victim=$!
for _ in $(seq 100); do
  [ -f "$work/dest/.run.partial-$victim/.chainmail-staging" ] && break
  sleep 0.1
done
sleep 0.5
kill -9 "$victim"; wait "$victim" 2>/dev/null
[ -d "$work/dest/.run.partial-$victim" ] || fail "the killed run left no staging folder to test on"
mkdir "$work/dest/.run.partial-999999999"  # a look-alike without the marker: not chainmail's
"$chainmail" run "$scene" "${small[@]}" --out "$work/dest/run" 2>"$work/err" ||
  fail "the run after the killed one: $(cat "$work/err")"
[ ! -e "$work/dest/.run.partial-$victim" ] || fail "the killed run's staging folder is still there"
[ -d "$work/dest/.run.partial-999999999" ] || fail "a folder without the marker was removed"
[ -f "$work/dest/run/summary.json" ] || fail "the second run wrote no summary"
grep -q chainmail-staging "$work/dest/run/.chainmail-manifest.json" && fail "the marker was kept"
echo "killed run: checked"

echo "a run writes $total bytes"
[ "$failures" = 0 ] && echo "all passed" || echo "$failures failed"
[ "$failures" = 0 ]
