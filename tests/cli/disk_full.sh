#!/usr/bin/env bash
# A full disk, for real: `style4d train` on a small tmpfs mounted in a private mount namespace
# (unshare: root, or an unprivileged user namespace). (1) A disk too small for the first checkpoint
# refuses before anything is written and leaves no run folder. (2) A disk that fills while training
# stops the run with one error line naming the file and "No space left on device", leaves no
# temporaries, and the run resumes once there is room again.
#   disk_full.sh STYLE4D_EXE        (exit 77: skipped, no mount namespace here)
set -uo pipefail
exe=$1
if [ -z "${S4D_DISK_FULL_NS:-}" ]; then
  ns=(unshare -m); [ "$(id -u)" -eq 0 ] || ns=(unshare -rm)
  "${ns[@]}" true 2>/dev/null || { echo "SKIP: cannot make a private mount namespace (${ns[*]}), so no tmpfs to fill"; exit 77; }
  S4D_DISK_FULL_NS=1 exec "${ns[@]}" "$0" "$@"
fi
work=$(mktemp -d /tmp/s4d_disk_full.XXXXXX)
disk=$work/disk
trap 'umount "$disk" 2>/dev/null; rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; for f in "$work"/*.err; do echo "--- $f"; tail -5 "$f"; done; exit 1; }
"$exe" synth --out "$work/data" --cams 4 --frames 3 --size 48x36 > "$work/synth.log" 2>&1 || fail "synth"
mkdir "$disk"
train=(train --data "$work/data" --out "$disk/run" --preset fast --stage static --max-time 0 --skip-check)

# (1) 64 KiB cannot hold one checkpoint (~1 MB here): refused at once, nothing left behind.
mount -t tmpfs -o size=64k tmpfs "$disk" || { echo "SKIP: cannot mount a tmpfs"; exit 77; }
"$exe" "${train[@]}" --iters 100 2> "$work/small.err"
rc=$?
[ $rc -eq 1 ] || fail "a disk too small: exit $rc, expected 1"
grep -q "^style4d train: error: $disk/run: .* free, a checkpoint of [0-9]* Gaussians" "$work/small.err" ||
  fail "a disk too small: no error line naming the run folder and the room needed"
[ ! -e "$disk/run" ] || fail "a refused run left $disk/run behind"
umount "$disk"

# (2) Room to start; the disk is filled once two checkpoints exist.
mount -t tmpfs -o size=24m tmpfs "$disk"
"$exe" "${train[@]}" --iters 3000 --checkpoint-every 10 2> "$work/fill.err" &
pid=$!
for _ in $(seq 1200); do
  [ -e "$disk/run/checkpoint/state.prev.s4dckpt" ] && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.1
done
[ -e "$disk/run/checkpoint/state.prev.s4dckpt" ] || fail "no second checkpoint within 120 s"
dd if=/dev/zero of="$disk/fill" bs=64k > /dev/null 2>&1
wait $pid
rc=$?
[ $rc -eq 1 ] || fail "disk filled while training: exit $rc, expected 1"
[ "$(grep -c '^style4d train: error: ' "$work/fill.err")" -eq 1 ] || fail "disk filled: expected one error line"
grep -q "^style4d train: error: .*$disk/run/.*No space left on device" "$work/fill.err" ||
  fail "disk filled: the error line does not name a file of the run and the full disk"
leftover=$(find "$disk/run" -name '*.tmp*')
[ -z "$leftover" ] || fail "temporaries left behind: $leftover"
rm "$disk/fill"
lines_before=$(wc -l < "$disk/run/loss.csv")
"$exe" train --resume "$disk/run" 2> "$work/resume.err" &
pid=$!
for _ in $(seq 1200); do  # trains on: loss.csv grows
  [ "$(wc -l < "$disk/run/loss.csv")" -gt "$lines_before" ] && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.1
done
kill -INT $pid 2>/dev/null
wait $pid
rc=$?
[ $rc -eq 130 ] || [ $rc -eq 0 ] || fail "resume after the disk was freed: exit $rc"
grep -q "error" "$work/resume.err" && fail "resume after the disk was freed reported an error"
[ "$(wc -l < "$disk/run/loss.csv")" -gt "$lines_before" ] || fail "resume after the disk was freed did not train on"
echo "disk_full: refused up front, stopped by name when full, resumed after"
