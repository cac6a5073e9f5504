#!/usr/bin/env bash
# The main job on the built-in default. Installs what is missing, builds, then
# runs ppp_inspect on the ZIM2 dataset in ../shared/data (observations together
# with orbits, clocks, antennas and biases, so it also checks product coverage),
# then solves it: ppp_solve --estimator both, kinematic GPS PPP with the forward
# EKF and the Bayes-tree smoother (filtered and smoothed), against the known
# station coordinates (one statistics table, notes, smoother update times), and
# draws the figures with scripts/plot_solutions.py (error profile, CDFs, bias
# convergence). Files and PNGs in results/ (git-ignored) or $PPP_DEMO_OUT.
#
#   ./scripts/demo.sh              # the default dataset
#   ./scripts/demo.sh FILE...      # your own files (RINEX obs/nav, CRX, SP3, CLK, ATX, BIA, BLQ; .gz ok)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

"$REPO_DIR/scripts/setup_deps.sh"
"$REPO_DIR/scripts/build.sh" > "$WS_DIR.build.log" 2>&1 || { tail -40 "$WS_DIR.build.log"; exit 1; }

if [ $# -gt 0 ]; then
  exec "$BIN_DIR/ppp_inspect" "$@"
fi

ZIM2="$SHARED_DATA/zim2-2026-133"
if [ ! -d "$ZIM2" ]; then
  cat >&2 <<MSG
demo.sh: no dataset given and the default one is missing ($ZIM2).
Give your own files:   ./scripts/demo.sh OBS.rnx ORBIT.sp3 CLOCK.clk [ANTENNAS.atx] [BIASES.bia]
or place the project's shared datasets at ../shared/data beside the repository
(or point PPP_SHARED_DATA at them).
MSG
  exit 2
fi
ATX="$SHARED_DATA/antex/igs20_zim2_gps_trim.atx"
"$BIN_DIR/ppp_inspect" \
  "$ZIM2/ZIM200CHE_R_20261330000_01H_30S_MO.rnx" \
  "$ZIM2/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3" \
  "$ZIM2/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK" \
  "$ZIM2/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz" \
  "$ATX"

OUT="${PPP_DEMO_OUT:-$REPO_DIR/results}"
echo
echo "=== ppp_solve: ZIM2, kinematic GPS PPP, EKF and smoother (truth: ../shared/data/README.md) ==="
"$BIN_DIR/ppp_solve" \
  --obs "$ZIM2/ZIM200CHE_R_20261330000_01H_30S_MO.rnx" \
  --sp3 "$ZIM2/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3" \
  --clk "$ZIM2/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK" \
  --bia "$ZIM2/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz" \
  --atx "$ATX" \
  --config "$REPO_DIR/config/ppp_real_data.yaml" \
  --estimator both \
  --truth 4331299.5841,567537.7070,4633133.9645 \
  --out "$OUT"

echo
echo "=== figures: scripts/plot_solutions.py -> $OUT/plots ==="
/usr/bin/python3 "$REPO_DIR/scripts/plot_solutions.py" --out "$OUT/plots" \
  --title "ZIM2 2026-133, kinematic GPS PPP" \
  "EKF=$OUT/zim2_ekf.csv" \
  "smoother filtered=$OUT/zim2_smoother_filtered.csv" \
  "smoother smoothed=$OUT/zim2_smoother_smoothed.csv" \
  --biases "smoother=$OUT/zim2_smoother_biases.csv"
