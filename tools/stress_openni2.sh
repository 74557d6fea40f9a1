#!/bin/bash
# Runs OpenNI2 work many times on a loaded machine and counts crashes and hangs: how the races
# in libOpenNI2 2.2 described in docs/openni2_device.md were measured.
#
#   tools/stress_openni2.sh BUILD_DIR playback RUNS [GTEST_FILTER]
#       runs BUILD_DIR/test/test_openni2_device (default filter: the two round-trip tests)
#   tools/stress_openni2.sh BUILD_DIR record RUNS
#       records data/kinect/grabber_sequence (3 frames) with pcl_texlet_record from the simulated
#       device, each run bounded by 60 s (a run killed then counts as hung)
#
# Two busy loops run beside, one per core of the 2-core CI machine. Crashed runs keep their
# output and core file in a temporary folder, named at the end. Needs root, as the tests do (the
# driver is bound over OpenNI2's driver folder in a private mount namespace; record mode does it
# with tools/oni_from_tiffs/make_oni.sh).
set -uo pipefail
if [ $# -lt 3 ] || { [ "$2" != playback ] && [ "$2" != record ]; }; then
  echo "usage: $0 BUILD_DIR playback|record RUNS [GTEST_FILTER]" >&2
  exit 2
fi
build="$(cd "$1" && pwd)" || exit 2
mode=$2
runs=$3
filter=${4:-*Survive*}
repo="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d /tmp/stress_openni2_XXXXXX)"
ulimit -c unlimited

( while :; do :; done ) & busy1=$!
( while :; do :; done ) & busy2=$!
trap 'kill $busy1 $busy2 2>/dev/null' EXIT

ok=0; crashed=0; hung=0; failed=0
for i in $(seq 1 "$runs"); do
  mkdir -p "$work/run$i"
  if [ "$mode" = playback ]; then
    (cd "$work/run$i" && GLIBC_TUNABLES=glibc.pthread.stack_cache_size=1073741824 \
      timeout -s KILL 300 "$build/test/test_openni2_device" --gtest_filter="$filter" > log 2>&1)
  else
    # make_oni.sh binds the built driver in a private mount namespace; timeout kills its group.
    (cd "$work/run$i" && timeout -s KILL 60 "$repo/tools/oni_from_tiffs/make_oni.sh" "$build" \
      "pcltexlet:recording=$repo/data/kinect/grabber_sequence;loop=0" 3 out.oni -q > log 2>&1)
  fi
  rc=$?
  case $rc in
    0) ok=$((ok + 1)); rm -rf "$work/run$i" ;;
    137) hung=$((hung + 1)); echo "run $i: killed after its time limit (hung)" ;;
    134|139) crashed=$((crashed + 1)); echo "run $i: crashed (exit $rc)" ;;
    *) failed=$((failed + 1)); echo "run $i: exit $rc: $(tail -1 "$work/run$i/log")" ;;
  esac
  printf '\r%d/%d runs' "$i" "$runs" >&2
done
echo >&2
echo "$mode: $runs runs, $ok passed, $crashed crashed, $hung hung, $failed failed"
if [ $((crashed + hung + failed)) -eq 0 ]; then rm -rf "$work"; else echo "their output and core files: $work"; fi
exit 0
