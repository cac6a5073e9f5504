#!/usr/bin/env bash
# Downloads the public 45-minute RTCM SC-134 SSR test set into a folder of your choice:
#   - SSRTEST_20260206_CORR.bin: RTCM-SSR orbit/clock (1057/1058, 1063/1064, 1240/1241),
#     code biases (1059/1065/1242), phase biases (1265-1267), VTEC (1264), GPS/Galileo
#     ephemerides (1019/1046); provider 260, solution 2; 1 Hz, 2026-02-06 20:00:39-20:46:07 GPST.
#   - ROVRMSG.bin, ROMAMSG.bin: two receivers' RTCM 3 MSM5 (GPS, GLONASS, Galileo) over the
#     same period, 1 Hz. The rover is static (reference position: doc/live_input.md).
# Source: https://github.com/hirokawa/cssrlib-data (licence MIT, "Copyright (c) 2022 Rui
# Hirokawa"), data/sc134/msg/ssr/, at pinned commits:
#   b0c59d99af14e78fd84a9c86eec2f9e64a38dc42  SSRTEST_20260206_CORR.bin (removed upstream later)
#   1ce510fad753a4d9599b3fc2a83053cfd7408120  ROVRMSG.bin, ROMAMSG.bin,
#                                             SSRTEST_20260206_CORR_v123.bin (with --v123)
# The set carries no broadcast file: its ephemerides do not cover the IODs its corrections
# name (doc/live_input.md, "The SC-134 test set"). Nothing here is copied into the project.
#
# With --has, also the Galileo HAS internet data distribution recording of the same
# repository (data/doy2023-229, commit 1ce510f): idd2023229c.rtc, RTCM 3 SSR (1059/1060,
# 1242/1243, provider 270) with the GPS and Galileo ephemerides (1019/1046), 2023-08-17
# 01:59:12-03:00:02 GPST, and OBE42023229c.nav, RINEX navigation converted from it. The
# station's observation file of that hour is not fetchable from the repository.
#
# usage: scripts/fetch_ssr_data.sh DIR [--v123] [--has]
set -euo pipefail

usage() { echo "usage: $0 DIR [--v123]" >&2; exit 2; }
[[ $# -ge 1 && $# -le 3 ]] || usage
DIR=$1
shift
V123=0
HAS=0
for opt in "$@"; do
  case $opt in
    --v123) V123=1 ;;
    --has) HAS=1 ;;
    *) usage ;;
  esac
done

BASE=https://raw.githubusercontent.com/hirokawa/cssrlib-data
OLD=b0c59d99af14e78fd84a9c86eec2f9e64a38dc42
HEAD=1ce510fad753a4d9599b3fc2a83053cfd7408120
SUB=data/sc134/msg/ssr

# name  commit  sha256 (empty: not known here, not checked)
FILES=(
  "SSRTEST_20260206_CORR.bin $OLD c000e9252c97fb3c773335a9c96e08d2f1df755dd687ac8580c8180d1cab0fdf"
  "ROVRMSG.bin $HEAD d5cf8cd24fae75750ed0e8d3f51b71741d80cecd1850232a3228a9e45d787d65"
  "ROMAMSG.bin $HEAD af8be3158e457bd05990481d2d515f0acc306a4e9e36d8acb25ac0afbc4d8f99"
)
[[ $V123 -eq 1 ]] && FILES+=("SSRTEST_20260206_CORR_v123.bin $HEAD -")
HAS_FILES=(
  "idd2023229c.rtc $HEAD dca0f6f6bdc497d3b6d794b19696d7b6590c328fb7a62000dd5a24815152f902"
  "OBE42023229c.nav $HEAD 19c14a0c37c95bc2e60b2a199ed5e716bb3db508e0b4afda0b8710296206de94"
)

fetch_one() {
  local name=$1 commit=$2 sum=$3 sub=${4:-$SUB} out="$DIR/$1"
  if [[ -s $out ]]; then echo "have $out"; else
    echo "fetching $name ($commit)"
    curl -fSL --retry 3 -o "$out.part" "$BASE/$commit/$sub/$name" || { rm -f "$out.part"; echo "error: download of $name failed" >&2; return 1; }
    mv "$out.part" "$out"
  fi
  if [[ $sum != - ]] && ! echo "$sum  $out" | sha256sum -c --quiet -; then
    echo "error: $out: SHA-256 differs from the pinned file's" >&2
    return 1
  fi
}

mkdir -p "$DIR"
status=0
for entry in "${FILES[@]}"; do
  # shellcheck disable=SC2086
  fetch_one $entry || status=1
done
if [[ $HAS -eq 1 ]]; then
  for entry in "${HAS_FILES[@]}"; do
    # shellcheck disable=SC2086
    fetch_one $entry data/doy2023-229 || status=1
  done
fi
[[ $status -eq 0 ]] && echo "done: $DIR (licence MIT, hirokawa/cssrlib-data)"
exit $status
