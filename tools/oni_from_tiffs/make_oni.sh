#!/bin/bash
# Records an .oni file from pcl_texlet's simulated OpenNI2 device (src/openni2_driver) with
# pcl_texlet_record, OpenNI2's own Recorder behind it (depth lossless).
#
#   tools/oni_from_tiffs/make_oni.sh BUILD_DIR DEVICE_URI FRAMES OUTPUT.oni [pcl_texlet_record options]
#
# The files in data/ were made with (from the repository root, after building):
#   make_oni.sh build 'pcltexlet:sim=box;effects=temporal_drift,vertical_stripes;seed=1;frames=30' 30 \
#     data/simulated/box_qvga.oni --size 320x240
#   make_oni.sh build "pcltexlet:recording=$PWD/data/kinect/grabber_sequence;loop=0" 3 grabber_sequence.oni
#
# Needs root: OpenNI2 (Debian 12) loads drivers only from its system driver folder, so a private
# mount namespace binds a temporary folder holding the built driver and the system's OniFile
# driver over it, leaving the system's drivers untouched.
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 BUILD_DIR DEVICE_URI FRAMES OUTPUT.oni [pcl_texlet_record options]" >&2
  exit 2
fi
build="$(cd "$1" && pwd)"
uri="$2"
frames="$3"
out="$(cd "$(dirname "$4")" && pwd)/$(basename "$4")"
shift 4
system_drivers=$(sed -n 's/^PCL_TEXLET_OPENNI2_DRIVER_DIR:PATH=//p' "$build/CMakeCache.txt")
system_drivers="${system_drivers:-/lib/x86_64-linux-gnu/OpenNI2/Drivers}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

mkdir -p "$work/drivers"
cp "$build/src/openni2_driver/libPclTexletDevice.so.0" "$system_drivers/libOniFile.so.0" "$work/drivers/"
unshare -m sh -c 'mount --make-rprivate / && mount --bind "$1" "$2" && shift 2 && exec "$@"' sh \
  "$work/drivers" "$system_drivers" \
  "$build/apps/pcl_texlet_record/pcl_texlet_record" -d "$uri" -n "$frames" "$@" "$out"
