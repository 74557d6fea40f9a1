#!/bin/bash
# Makes data/kinect/grabber_sequence.oni: the three real Kinect depth frames of
# data/kinect/grabber_sequence/tiff recorded by OpenNI2's own Recorder (lossless), through the
# replay driver of this folder. Needs root: OpenNI2 (Debian 12) loads drivers only from
# /lib/x86_64-linux-gnu/OpenNI2/Drivers, so a private mount namespace binds a folder holding the
# OniFile driver and the replay driver over it, leaving the system's drivers untouched.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
out="${1:-$repo/data/kinect/grabber_sequence.oni}"
system_drivers=/lib/x86_64-linux-gnu/OpenNI2/Drivers
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

mkdir -p "$work/drivers"
# Debian's OpenNI2 loads lib*.so.0 from its driver folder.
c++ -std=c++17 -O2 -fPIC -shared -I/usr/include/openni2 "$here/tiff_replay_driver.cpp" -ltiff \
  -o "$work/drivers/libTiffReplay.so.0"
c++ -std=c++17 -O2 -I/usr/include/openni2 "$here/record_oni.cpp" -lOpenNI2 -o "$work/record_oni"
cp "$system_drivers/libOniFile.so.0" "$work/drivers/"

unshare -m sh -c "mount --bind '$work/drivers' '$system_drivers' && \
  '$work/record_oni' 'tiffreplay:$repo/data/kinect/grabber_sequence/tiff' '$out' 3"
