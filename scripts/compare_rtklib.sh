#!/usr/bin/env bash
# Peer comparison: runs Debian's RTKLIB rnx2rtkp (2.4.3) on a dataset of
# ../shared/data with config/rtklib_ppp_kinematic.conf and prints its position
# error statistics, side by side with any number of our .pos files, all computed
# by the same code (ppp_pos_stats). Both programs are timed as whole processes.
#
# usage: scripts/compare_rtklib.sh DATASET_DIR [--solve ekf|smoother|both] [[LABEL=]POS_FILE ...]
#   DATASET_DIR: e.g. ../shared/data/zim2-2026-133 or ../shared/data/ccj2-2021-210
#   POS_FILE: e.g. the DIR/<name>_ekf.pos that ppp_solve writes; LABEL names its
#     column (no commas; default "ours", "ours2", ...)
#   --solve E: also runs ppp_solve --estimator E on the same inputs (with
#     config/ppp_real_data.yaml and the dataset's truth; output in WORK/ppp_solve),
#     times it as a whole process like rnx2rtkp, and adds its .pos files as the
#     columns "EKF", "smoother filtered", "smoother smoothed"
# Environment: PPP_BIN_DIR (where ppp_pos_stats, ppp_rtklib_inputs and ppp_solve
# are; default the catkin devel space), PPP_COMPARE_DIR (work directory; default a
# temp dir).
#
# RTKLIB's inputs are written by our own tool ppp_rtklib_inputs from our readers:
#  * a GPS navigation file whose clock terms come from the precise clock file
#    (rnx2rtkp needs a broadcast record per satellite even in precise mode);
#  * a GPS-only SP3-c copy of the orbits (RTKLIB 2.4.3 reads at most 99 satellites).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

usage() { echo "usage: $0 DATASET_DIR [--solve ekf|smoother|both] [[LABEL=]POS_FILE ...]" >&2; exit 2; }
[[ $# -ge 1 ]] || usage
DATASET="$(cd "$1" && pwd -P)"
shift
SOLVE=""
POS_FILES=()
POS_LABELS=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --solve)
      [[ $# -ge 2 ]] || usage
      case "$2" in ekf|smoother|both) SOLVE="$2" ;; *) echo "--solve: unknown estimator '$2'" >&2; usage ;; esac
      shift 2 ;;
    -*) echo "unknown option $1" >&2; usage ;;
    *=*) POS_LABELS+=("${1%%=*}"); POS_FILES+=("${1#*=}"); shift ;;
    *) # unlabelled: "ours", then "ours2", "ours3", ...
      label="ours"
      if [[ ${#POS_FILES[@]} -gt 0 ]]; then label="ours$((${#POS_FILES[@]} + 1))"; fi
      POS_LABELS+=("$label"); POS_FILES+=("$1"); shift ;;
  esac
done
for l in "${POS_LABELS[@]}"; do [[ "$l" != *,* ]] || { echo "label '$l' has a comma" >&2; exit 2; }; done
for f in "${POS_FILES[@]}"; do [[ -r "$f" ]] || { echo "cannot read $f" >&2; exit 1; }; done
BIN="${PPP_BIN_DIR:-$BIN_DIR}"
ANTEX_DIR="$(cd "$DATASET/.." && pwd -P)/antex"
TOOLS=(ppp_pos_stats ppp_rtklib_inputs)
[[ -z "$SOLVE" ]] || TOOLS+=(ppp_solve)
for tool in "${TOOLS[@]}"; do
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
    BIA="$DATASET/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz"
    OUR_ATX=("$SAT_ATX")
    TRUTH="4331299.5841,567537.7070,4633133.9645" ;;
  ccj2-*)
    OBS="$DATASET/ccj22100.21o"
    SP3="$DATASET/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"
    CLK="$DATASET/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"
    # GPS satellites from the 1992-2026 file; the receiver TRM59800.00 SCIS has no
    # calibration here, RTKLIB falls back on TRM59800.00 NONE from the ZIM2 file.
    SAT_ATX="$ANTEX_DIR/igs20_gps_satellites_trim.atx"
    RCV_ATX="$ANTEX_DIR/igs20_zim2_gps_trim.atx"
    BIA="$DATASET/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz"
    OUR_ATX=("$SAT_ATX" "$RCV_ATX")  # searched in order: satellites, then the receiver
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

seconds() { echo "$1 - $2" | bc -l | sed 's/^\./0./'; }
RTKLIB_S=$(seconds "$T1" "$T0")
echo "dataset $NAME, truth $TRUTH; RTKLIB output $WORK/$NAME.rtklib.pos"
echo "rnx2rtkp wall time: $RTKLIB_S s"

if [[ -n "$SOLVE" ]]; then
  OUT="$WORK/ppp_solve"
  T0=$(date +%s.%N)
  "$BIN/ppp_solve" --obs "$OBS" --sp3 "$SP3" --clk "$CLK" --bia "$BIA" --atx "${OUR_ATX[@]}" \
    --config "$REPO_DIR/config/ppp_real_data.yaml" --estimator "$SOLVE" --truth "$TRUTH" \
    --name "$NAME" --out "$OUT" > "$WORK/ppp_solve.log" 2>&1 || {
    echo "ppp_solve failed, see $WORK/ppp_solve.log" >&2; tail -5 "$WORK/ppp_solve.log" >&2; exit 1; }
  T1=$(date +%s.%N)
  SOLVE_S=$(seconds "$T1" "$T0")
  echo "ppp_solve --estimator $SOLVE wall time: $SOLVE_S s (rnx2rtkp / ppp_solve = $(echo "$RTKLIB_S / $SOLVE_S" | bc -l | xargs printf '%.2f')); log $WORK/ppp_solve.log"
  grep -E "^smoother per epoch" "$WORK/ppp_solve.log" || true
  if [[ "$SOLVE" != smoother ]]; then POS_LABELS+=("EKF"); POS_FILES+=("$OUT/${NAME}_ekf.pos"); fi
  if [[ "$SOLVE" != ekf ]]; then
    POS_LABELS+=("smoother filtered" "smoother smoothed")
    POS_FILES+=("$OUT/${NAME}_smoother_filtered.pos" "$OUT/${NAME}_smoother_smoothed.pos")
  fi
fi

LABELS="RTKLIB forward"
for l in "${POS_LABELS[@]}"; do LABELS+=",$l"; done
"$BIN/ppp_pos_stats" "$WORK/$NAME.rtklib.pos" "${POS_FILES[@]}" --truth "$TRUTH" --labels "$LABELS" \
  --json "$WORK/$NAME.rtklib.stats.json"
