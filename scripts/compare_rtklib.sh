#!/usr/bin/env bash
# Peer comparison: runs Debian's RTKLIB rnx2rtkp (2.4.3) on a dataset of
# ../shared/data with config/rtklib_ppp_kinematic.conf and prints its position
# error statistics, side by side with ours when a .pos file of ours is given,
# all computed by the same code (ppp_pos_stats).
#
# usage: scripts/compare_rtklib.sh DATASET_DIR [OUR_POS_FILE]
#   OUR_POS_FILE: e.g. the DIR/<name>_ekf.pos that ppp_solve writes
#   DATASET_DIR: e.g. ../shared/data/zim2-2026-133 or ../shared/data/ccj2-2021-210
# Environment: PPP_BIN_DIR (where ppp_pos_stats and ppp_rtklib_inputs are; default
# the catkin devel space), PPP_COMPARE_DIR (work directory; default a temp dir).
#
# RTKLIB's inputs are written by our own tool ppp_rtklib_inputs from our readers:
#  * a GPS navigation file whose clock terms come from the precise clock file
#    (rnx2rtkp needs a broadcast record per satellite even in precise mode);
#  * a GPS-only SP3-c copy of the orbits (RTKLIB 2.4.3 reads at most 99 satellites).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

if [[ $# -lt 1 || $# -gt 2 ]]; then
  echo "usage: $0 DATASET_DIR [OUR_POS_FILE]" >&2
  exit 2
fi
DATASET="$(cd "$1" && pwd -P)"
OUR_POS="${2:-}"
BIN="${PPP_BIN_DIR:-$BIN_DIR}"
ANTEX_DIR="$(cd "$DATASET/.." && pwd -P)/antex"
for tool in ppp_pos_stats ppp_rtklib_inputs; do
  [[ -x "$BIN/$tool" ]] || { echo "missing $BIN/$tool (build first or set PPP_BIN_DIR)" >&2; exit 1; }
done
command -v rnx2rtkp >/dev/null || { echo "rnx2rtkp not found (apt install rtklib)" >&2; exit 1; }

# Per-dataset files and truth (../shared/data/README.md).
case "$(basename "$DATASET")" in
  zim2-*)
    OBS="$DATASET/ZIM200CHE_R_20261330000_01H_30S_MO.rnx"
    SP3="$DATASET/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"
    CLK="$DATASET/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"
    SAT_ATX="$ANTEX_DIR/igs20_zim2_gps_trim.atx"
    RCV_ATX="$ANTEX_DIR/igs20_zim2_gps_trim.atx"
    TRUTH="4331299.5841,567537.7070,4633133.9645" ;;
  ccj2-*)
    OBS="$DATASET/ccj22100.21o"
    SP3="$DATASET/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"
    CLK="$DATASET/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"
    # GPS satellites from the 1992-2026 file; the receiver TRM59800.00 SCIS has no
    # calibration here, RTKLIB falls back on TRM59800.00 NONE from the ZIM2 file.
    SAT_ATX="$ANTEX_DIR/igs20_gps_satellites_trim.atx"
    RCV_ATX="$ANTEX_DIR/igs20_zim2_gps_trim.atx"
    TRUTH="-4490605.094,3483895.065,2884928.334" ;;
  *) echo "unknown dataset $DATASET (expected zim2-* or ccj2-*)" >&2; exit 2 ;;
esac

WORK="${PPP_COMPARE_DIR:-$(mktemp -d /tmp/ppp_compare_rtklib.XXXXXX)}"
mkdir -p "$WORK"
NAME="$(basename "$DATASET")"
"$BIN/ppp_rtklib_inputs" nav "$WORK/$NAME.nav" "$CLK"
"$BIN/ppp_rtklib_inputs" sp3 "$WORK/$NAME.sp3" "$SP3"
# rnx2rtkp reads plain clock files only
case "$CLK" in *.gz) gzip -dc "$CLK" > "$WORK/$NAME.clk" ;; *) cp "$CLK" "$WORK/$NAME.clk" ;; esac
sed -e "s|^file-satantfile .*|file-satantfile    =$SAT_ATX|" \
    -e "s|^file-rcvantfile .*|file-rcvantfile    =$RCV_ATX|" \
    "$REPO_DIR/config/rtklib_ppp_kinematic.conf" > "$WORK/rtklib.conf"
T0=$(date +%s.%N)
rnx2rtkp -k "$WORK/rtklib.conf" -o "$WORK/$NAME.rtklib.pos" \
  "$OBS" "$WORK/$NAME.nav" "$WORK/$NAME.sp3" "$WORK/$NAME.clk" 2>"$WORK/rnx2rtkp.log" || {
  echo "rnx2rtkp failed, see $WORK/rnx2rtkp.log" >&2; exit 1; }
T1=$(date +%s.%N)

echo "dataset $NAME, truth $TRUTH; RTKLIB output $WORK/$NAME.rtklib.pos"
echo "rnx2rtkp wall time: $(echo "$T1 - $T0" | bc -l | sed 's/^\./0./') s"
if [[ -n "$OUR_POS" ]]; then
  "$BIN/ppp_pos_stats" "$WORK/$NAME.rtklib.pos" "$OUR_POS" --truth "$TRUTH" --labels "RTKLIB,ours" \
    --json "$WORK/$NAME.rtklib.stats.json"
else
  "$BIN/ppp_pos_stats" "$WORK/$NAME.rtklib.pos" --truth "$TRUTH" --labels "RTKLIB" \
    --json "$WORK/$NAME.rtklib.stats.json"
fi
