#!/usr/bin/env bash
# The main job, on a fresh machine with no data given:
#  1. installs what is missing (setup_deps.sh) and builds (build.sh);
#  2. makes a replay bag: a simulated UAV flight (ppp_to_bag --simulate, with its
#     truth trajectory; GPS + Galileo with integer ambiguities and the satellite
#     phase biases published with the products, config/simulation_ar.yaml), or
#     your own files with --data DIR;
#  3. runs its own roscore (a free port), both nodes side by side and the bag
#     replay: launch/compare.launch (ppp_ekf_node in ns ekf, ppp_smoother_node in
#     ns smoother, one rosbag player);
#  4. records the nodes' outputs (rosbag record of /ekf/ppp/* and /smoother/ppp/*);
#  5. prints ONE comparison table (ppp_bag_report: EKF, smoother filtered and
#     smoother smoothed against the truth, 3D error median/mean/sigma/max over all
#     epochs and the first 15 min, time to stay below 10 / 5 cm, PPP-AR fixed
#     share and time to first fix, node update time median/p99, epochs
#     processed/dropped);
#  6. writes per-estimator CSVs, the report JSON and the plots
#     (scripts/plot_solutions.py) to results/ (git-ignored; or $PPP_DEMO_OUT).
#
#   ./scripts/demo.sh                       simulated survey flight (lawn-mower mapping lines), 25 min at 1 Hz, replayed at 15x,
#                                           GPS + Galileo, both nodes with integer ambiguity resolution (PPP-AR)
#   ./scripts/demo.sh --float               the same flight with float ambiguities (ambiguity_resolution.enabled false)
#   ./scripts/demo.sh --rviz                the same with RViz (rviz/ppp.rviz; needs a display)
#   ./scripts/demo.sh --data DIR [--atx F.atx]... [--truth X,Y,Z]
#                                           your RINEX obs + SP3 + CLK (+ BIA) found in DIR by name
#   ./scripts/demo.sh --offline [FILE...]   the offline flow: ppp_inspect + ppp_solve --estimator both
#                                           on ZIM2 (../shared/data), or ppp_inspect on your files
# Options: --profile loiter|survey|figure8|climb, --duration-min N, --seed S, --float (simulation),
#          --rate R (replay speed factor; default 15 simulated, 30 --data), --out DIR,
#          --no-setup (skip setup_deps.sh/build.sh: already built).
# Exits non-zero with a message when a step fails; roscore and the nodes are
# stopped on exit; a node that dies or a replay that overruns its time limit
# ends the run.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

die() { echo "demo.sh: ERROR: $*" >&2; exit 1; }
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }

MODE=simulated DATA="" RVIZ=false RATE="" PROFILE=survey DURATION_MIN=25 SEED=1 SETUP=true AR=true
TRUTH="" ATX=() OFFLINE_ARGS=()
OUT="${PPP_DEMO_OUT:-$REPO_DIR/results}"
while [ $# -gt 0 ]; do
  case "$1" in
    --offline) MODE=offline; shift; OFFLINE_ARGS=("$@"); break ;;
    --data) DATA="${2:?--data needs a directory}"; MODE=data; shift 2 ;;
    --atx) ATX+=("${2:?--atx needs a file}"); shift 2 ;;
    --truth) TRUTH="${2:?--truth needs X,Y,Z}"; shift 2 ;;
    --rviz) RVIZ=true; shift ;;
    --rate) RATE="${2:?--rate needs a factor}"; shift 2 ;;
    --profile) PROFILE="${2:?}"; shift 2 ;;
    --duration-min) DURATION_MIN="${2:?}"; shift 2 ;;
    --seed) SEED="${2:?}"; shift 2 ;;
    --out) OUT="${2:?}"; shift 2 ;;
    --no-setup) SETUP=false; shift ;;
    --float) AR=false; shift ;;
    -h|--help) usage 0 ;;
    *) echo "demo.sh: unknown argument $1" >&2; usage 2 ;;
  esac
done

T_START=$SECONDS
if $SETUP; then
  "$REPO_DIR/scripts/setup_deps.sh"
  echo "=== building (log: $WS_DIR.build.log) ==="
  "$REPO_DIR/scripts/build.sh" > "$WS_DIR.build.log" 2>&1 || { tail -40 "$WS_DIR.build.log"; die "build failed (see $WS_DIR.build.log)"; }
fi
[ -f "$WS_DIR/devel/setup.bash" ] || die "no catkin workspace at $WS_DIR (run without --no-setup)"

# ---------------------------------------------------------------------------
# --offline: the previous demo (ppp_inspect + ppp_solve on ZIM2, no ROS).
# ---------------------------------------------------------------------------
if [ "$MODE" = offline ]; then
  if [ ${#OFFLINE_ARGS[@]} -gt 0 ]; then exec "$BIN_DIR/ppp_inspect" "${OFFLINE_ARGS[@]}"; fi
  ZIM2="$SHARED_DATA/zim2-2026-133"
  [ -d "$ZIM2" ] || die "the offline demo needs the ZIM2 dataset at $ZIM2 (or PPP_SHARED_DATA); give files: ./scripts/demo.sh --offline OBS SP3 CLK [ATX] [BIA]"
  ATXZ="$SHARED_DATA/antex/igs20_zim2_gps_trim.atx"
  "$BIN_DIR/ppp_inspect" "$ZIM2/ZIM200CHE_R_20261330000_01H_30S_MO.rnx" "$ZIM2/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3" \
    "$ZIM2/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK" "$ZIM2/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz" "$ATXZ"
  echo
  echo "=== ppp_solve: ZIM2, kinematic GPS PPP, EKF and smoother (truth: ../shared/data/README.md) ==="
  "$BIN_DIR/ppp_solve" --obs "$ZIM2/ZIM200CHE_R_20261330000_01H_30S_MO.rnx" \
    --sp3 "$ZIM2/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3" --clk "$ZIM2/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK" \
    --bia "$ZIM2/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz" --atx "$ATXZ" \
    --config "$REPO_DIR/config/ppp_real_data.yaml" --estimator both \
    --truth 4331299.5841,567537.7070,4633133.9645 --out "$OUT"
  echo
  echo "=== figures: scripts/plot_solutions.py -> $OUT/plots ==="
  /usr/bin/python3 "$REPO_DIR/scripts/plot_solutions.py" --out "$OUT/plots" --title "ZIM2 2026-133, kinematic GPS PPP" \
    "EKF=$OUT/zim2_ekf.csv" "smoother filtered=$OUT/zim2_smoother_filtered.csv" \
    "smoother smoothed=$OUT/zim2_smoother_smoothed.csv" --biases "smoother=$OUT/zim2_smoother_biases.csv" \
    --residuals "EKF=$OUT/zim2_ekf_residuals.csv"
  exit 0
fi

# ---------------------------------------------------------------------------
# 2. the replay bag and its truth
# ---------------------------------------------------------------------------
# shellcheck disable=SC1091
set +u; source "$WS_DIR/devel/setup.bash"; set -u
WORK="$OUT/replay"
mkdir -p "$WORK"
INPUT_BAG="$WORK/input.bag" RECORDED_BAG="$WORK/recorded.bag"
rm -f "$INPUT_BAG" "$RECORDED_BAG" "$RECORDED_BAG.active"
OVERRIDES="" EXTRA_CONFIG="" TRUTH_ARGS=() NAME="" TITLE=""

# The one file of DIR whose name matches an extended regex (case-insensitive); "" when none.
find_one() {  # dir regex what
  local hits
  mapfile -t hits < <(find "$1" -maxdepth 1 -type f | grep -iE "$2" | sort)
  if [ ${#hits[@]} -gt 1 ]; then echo "demo.sh: several $3 files in $1, using ${hits[0]##*/}" >&2; fi
  [ ${#hits[@]} -gt 0 ] && echo "${hits[0]}" || true
}

if [ "$MODE" = simulated ]; then
  NAME="sim_$PROFILE"
  AR_TEXT="integer ambiguity resolution"
  $AR || AR_TEXT="float ambiguities"
  TITLE="simulated $PROFILE flight, ${DURATION_MIN} min at 1 Hz, GPS + Galileo, $AR_TEXT, ROS replay"
  RATE="${RATE:-15}"
  echo "=== 2. simulated UAV flight: $PROFILE, $DURATION_MIN min at 1 Hz, GPS + Galileo with phase biases (seed $SEED) -> $INPUT_BAG ==="
  "$BIN_DIR/ppp_to_bag" --simulate "$PROFILE" --duration-min "$DURATION_MIN" --rate 1 --seed "$SEED" \
    --config "$REPO_DIR/config/simulation_ar.yaml" --truth-out "$WORK/truth.csv" --out "$INPUT_BAG" \
    || die "ppp_to_bag --simulate failed"
  OVERRIDES="$REPO_DIR/config/ppp_simulated.yaml"
  # Both systems of the flight, and PPP-AR on (the bag's corrections carry the phase biases).
  EXTRA_CONFIG="$WORK/ambiguities.yaml"
  {
    echo "# written by scripts/demo.sh: the simulated flight's systems and the ambiguity mode ($AR_TEXT)"
    echo "measurement_model: {signals: {systems: [GPS, Galileo]}}"
    echo "ambiguity_resolution: {enabled: $AR}"
  } > "$EXTRA_CONFIG"
  TRUTH_ARGS=(--truth-csv "$WORK/truth.csv")
else
  [ -d "$DATA" ] || die "--data $DATA: not a directory"
  DATA="$(cd "$DATA" && pwd -P)"
  RATE="${RATE:-30}"
  OBS="$(find_one "$DATA" '(_MO\.rnx|\.rnx|\.[0-9][0-9]o|\.crx|\.[0-9][0-9]d)(\.gz)?$' observation)"
  SP3="$(find_one "$DATA" '\.sp3(\.gz)?$' SP3)"
  CLK="$(find_one "$DATA" '\.clk(\.gz)?$' clock)"
  BIA="$(find_one "$DATA" '\.bia(\.gz)?$' bias)"
  [ -n "$OBS" ] || die "no RINEX observation file (*.rnx, *.YYo, *.crx, optionally .gz) in $DATA"
  [ -n "$SP3" ] || die "no SP3 orbit file (*.sp3[.gz]) in $DATA"
  [ -n "$CLK" ] || die "no RINEX clock file (*.clk[.gz]) in $DATA"
  # The marker name (RINEX header, MARKER NAME) names the run and recognises the shared datasets.
  MARKER="$( (zcat -f "$OBS" 2>/dev/null || true) | head -60 | grep 'MARKER NAME' | cut -c1-60 | tr -d ' ' | head -1 || true)"
  MARKER="${MARKER:-$(basename "$OBS" | cut -c1-4)}"
  NAME="$(echo "$MARKER" | cut -c1-4 | tr 'A-Z' 'a-z')"
  # Antennas: --atx, else the shared datasets' files (../shared/data/README.md), else *.atx in DIR or DIR/../antex.
  if [ ${#ATX[@]} -eq 0 ]; then
    case "$NAME" in
      zim2) [ -f "$DATA/../antex/igs20_zim2_gps_trim.atx" ] && ATX=("$DATA/../antex/igs20_zim2_gps_trim.atx") ;;
      ccj2) for f in igs20_gps_satellites_trim.atx igs20_zim2_gps_trim.atx; do
              [ -f "$DATA/../antex/$f" ] && ATX+=("$DATA/../antex/$f"); done ;;
    esac
  fi
  if [ ${#ATX[@]} -eq 0 ]; then
    mapfile -t ATX < <(find "$DATA" "$DATA/../antex" -maxdepth 1 -type f -iname '*.atx' 2>/dev/null | sort)
  fi
  [ ${#ATX[@]} -gt 0 ] || die "no ANTEX file: give --atx FILE.atx (or put it in $DATA or $DATA/../antex)"
  # Truth: --truth, else the shared datasets' known coordinates (../shared/data/README.md).
  if [ -z "$TRUTH" ]; then
    case "$NAME" in
      zim2) TRUTH=4331299.5841,567537.7070,4633133.9645 ;;   # ITRF2020 propagated to 2026-05-13
      ccj2) TRUTH=-4490605.094,3483895.065,2884928.334 ;;    # WUM clock file header, 2021-07-29
    esac
  fi
  if [ -z "$TRUTH" ]; then
    TRUTH="$( (zcat -f "$OBS" 2>/dev/null || true) | head -60 | grep 'APPROX POSITION XYZ' | head -1 | awk '{print $1","$2","$3}' || true)"
    [ -n "$TRUTH" ] || die "no truth: give --truth X,Y,Z (ECEF, m)"
    echo "demo.sh: WARNING: no --truth given: errors are against the RINEX header's APPROX POSITION XYZ ($TRUTH), a rough position, not a truth" >&2
  fi
  TRUTH_ARGS=(--truth "$TRUTH")
  OVERRIDES="$REPO_DIR/config/ppp_ros_zim2.yaml"  # the real-data overrides of ppp_real_data.yaml for the nodes
  EXTRA_CONFIG="$WORK/products.yaml"
  {
    echo "# written by scripts/demo.sh: the product files of $DATA"
    echo "ros:"
    echo "  products:"
    echo "    atx: [$(printf '"%s", ' "${ATX[@]}" | sed 's/, $//')]"
    [ -n "$BIA" ] && echo "    bias: \"$BIA\""
  } > "$EXTRA_CONFIG"
  TITLE="$MARKER ($(basename "$OBS")), kinematic GPS PPP, ROS replay"
  echo "=== 2. $DATA -> $INPUT_BAG ==="
  BIA_NAME=none
  [ -n "$BIA" ] && BIA_NAME="$(basename "$BIA")"
  echo "  observations $(basename "$OBS"), orbits $(basename "$SP3"), clocks $(basename "$CLK"), biases $BIA_NAME"
  echo "  antennas ${ATX[*]}; truth $TRUTH"
  BIA_ARGS=()
  [ -n "$BIA" ] && BIA_ARGS=(--bia "$BIA")
  "$BIN_DIR/ppp_to_bag" --obs "$OBS" --sp3 "$SP3" --clk "$CLK" "${BIA_ARGS[@]}" --out "$INPUT_BAG" \
    || die "ppp_to_bag failed on $DATA"
fi
# Replay length [s of bag time] for the time limit.
BAG_S="$(rosbag info -y -k duration "$INPUT_BAG" 2>/dev/null | cut -d. -f1)"
[[ "$BAG_S" =~ ^[0-9]+$ ]] || die "cannot read the duration of $INPUT_BAG"

# ---------------------------------------------------------------------------
# 3./4. roscore, both nodes, the player and the recorder (compare.launch)
# ---------------------------------------------------------------------------
PORT="$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://localhost:$PORT" ROS_HOME="$WORK/ros"
mkdir -p "$ROS_HOME"
CORE_PID="" LAUNCH_PID=""
stop_group() {  # pid: SIGINT to its process group, then TERM, then KILL
  local pid="$1" k
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -INT -- "-$pid" 2>/dev/null || true
  for k in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.2; done
  kill -TERM -- "-$pid" 2>/dev/null || true
  sleep 1
  kill -KILL -- "-$pid" 2>/dev/null || true
}
cleanup() {
  stop_group "$LAUNCH_PID"
  stop_group "$CORE_PID"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "=== 3. roscore on port $PORT (logs: $ROS_HOME/log) ==="
setsid roscore -p "$PORT" > "$WORK/roscore.log" 2>&1 &
CORE_PID=$!
for _ in $(seq 1 60); do
  rosparam get /rosdistro > /dev/null 2>&1 && break
  kill -0 "$CORE_PID" 2>/dev/null || { cat "$WORK/roscore.log"; die "roscore exited"; }
  sleep 0.5
done
rosparam get /rosdistro > /dev/null 2>&1 || die "roscore did not come up on port $PORT within 30 s"

RVIZ_ARG=false
if $RVIZ; then
  if [ -n "${DISPLAY:-}" ] && command -v rviz > /dev/null; then RVIZ_ARG=true
  elif [ -z "${DISPLAY:-}" ]; then echo "demo.sh: --rviz: no DISPLAY (no graphical session): RViz not started; the run goes on without it"
  else echo "demo.sh: --rviz: rviz is not installed: RViz not started"; fi
fi
# smoother_memory:=full: the demo's bag is minutes long, and its table compares the full smoother.
LAUNCH_ARGS=(bag:="$INPUT_BAG" rate:="$RATE" overrides:="$OVERRIDES" smoother_memory:=full record:=true record_out:="$RECORDED_BAG"
             rviz:="$RVIZ_ARG")
[ -n "$EXTRA_CONFIG" ] && LAUNCH_ARGS+=(extra_config:="$EXTRA_CONFIG")
[ -n "${PPP_DEMO_SMOOTHER_LAUNCH:-}" ] && LAUNCH_ARGS+=(smoother_launch:="$PPP_DEMO_SMOOTHER_LAUNCH")  # tests only
LIMIT_S="$(awk -v b="$BAG_S" -v r="$RATE" 'BEGIN { if (!(r > 0)) exit 1; printf "%d", b / r + 90 }')" || die "--rate must be > 0"
echo "=== 3./4. compare.launch: ppp_ekf_node (ns ekf) + ppp_smoother_node (ns smoother), ${BAG_S} s of bag at ${RATE}x, recording -> $RECORDED_BAG (limit ${LIMIT_S} s; log $WORK/launch.log) ==="
setsid roslaunch "$REPO_DIR/launch/compare.launch" "${LAUNCH_ARGS[@]}" > "$WORK/launch.log" 2>&1 &
LAUNCH_PID=$!
T0=$SECONDS
while :; do
  if grep -qE '\[player-[0-9]+\] process has finished cleanly' "$WORK/launch.log"; then break; fi
  if grep -qE '\[(ekf/ppp_ekf_node|smoother/ppp_smoother_node|recorder|player)-[0-9]+\] process has died' "$WORK/launch.log"; then
    grep -E 'process has died|FATAL|ERROR' "$WORK/launch.log" | head -20 >&2
    die "a node died during the replay (see $WORK/launch.log and $ROS_HOME/log)"
  fi
  if ! kill -0 "$LAUNCH_PID" 2>/dev/null; then tail -30 "$WORK/launch.log" >&2; die "roslaunch exited early (see $WORK/launch.log)"; fi
  if [ $((SECONDS - T0)) -gt "$LIMIT_S" ]; then die "the replay did not finish within ${LIMIT_S} s (see $WORK/launch.log)"; fi
  sleep 1
done
echo "replay finished in $((SECONDS - T0)) s; letting the nodes finish"
sleep 3
stop_group "$LAUNCH_PID"
LAUNCH_PID=""
[ -f "$RECORDED_BAG" ] || die "the recorder wrote no $RECORDED_BAG (see $WORK/launch.log)"

# ---------------------------------------------------------------------------
# 5./6. the table, the CSVs and the plots
# ---------------------------------------------------------------------------
echo
echo "=== 5. ppp_bag_report: $TITLE ==="
set +e
"$BIN_DIR/ppp_bag_report" --bag "$RECORDED_BAG" --input "$INPUT_BAG" "${TRUTH_ARGS[@]}" --out "$OUT" --name "$NAME"
REPORT_RC=$?
set -e
[ $REPORT_RC -eq 0 ] || [ $REPORT_RC -eq 3 ] || die "ppp_bag_report failed (exit $REPORT_RC)"

echo
echo "=== 6. figures: scripts/plot_solutions.py -> $OUT/plots ==="
PLOTS=()
for k in "EKF=ekf" "smoother filtered=smoother_filtered" "smoother smoothed=smoother_smoothed"; do
  f="$OUT/${NAME}_${k#*=}.csv"
  [ -f "$f" ] && PLOTS+=("${k%%=*}=$f")
done
[ ${#PLOTS[@]} -gt 0 ] || die "no solution CSV to plot"
/usr/bin/python3 "$REPO_DIR/scripts/plot_solutions.py" --out "$OUT/plots" --title "$TITLE" "${PLOTS[@]}" \
  || die "plot_solutions.py failed"
echo
echo "demo.sh: done in $((SECONDS - T_START)) s: table above; files in $OUT (${NAME}_*.csv, ${NAME}_report.json, plots/), bags in $WORK"
[ $REPORT_RC -eq 0 ] || die "some rows of the table are missing (see the messages above the table)"
