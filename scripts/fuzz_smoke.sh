#!/usr/bin/env bash
# Builds every reader's libFuzzer target (test/fuzz/fuzz_<reader>.cpp) with
# clang + ASan/UBSan and runs each for a short time over its seed corpus
# (test/fuzz/corpus/<reader>) and its malformed fixtures
# (test/fixtures/malformed/<reader>). Writes one JUnit result per target into
# the directory given as $1. PPP_FUZZ_SECONDS sets the time per target (10 s).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
OUT="${1:?usage: fuzz_smoke.sh RESULT_DIR}"
SECONDS_PER_TARGET="${PPP_FUZZ_SECONDS:-10}"
FUZZ_BUILD="$WS_DIR/fuzz"
mkdir -p "$OUT"

junit() { write_junit "$OUT/fuzz-$1.xml" fuzz_smoke "$1" "$2" "$3"; }  # name status message

mapfile -t sources < <(ls "$REPO_DIR"/test/fuzz/fuzz_*.cpp 2>/dev/null)
if [ ${#sources[@]} -eq 0 ]; then
  echo "fuzz_smoke: no fuzz targets"
  exit 0
fi
if ! command -v clang++ >/dev/null; then
  for s in "${sources[@]}"; do junit "$(basename "$s" .cpp)" skipped "clang++ not installed"; done
  echo "fuzz_smoke: clang++ not installed: fuzz targets skipped"
  exit 0
fi

if ! { cmake -S "$REPO_DIR" -B "$FUZZ_BUILD" -DPPP_CORE_ONLY=ON -DPPP_BUILD_FUZZERS=ON \
         -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=RelWithDebInfo \
         > "$FUZZ_BUILD.log" 2>&1 &&
       targets=$(for s in "${sources[@]}"; do basename "$s" .cpp; done) &&
       make -C "$FUZZ_BUILD" -j"$JOBS" $targets >> "$FUZZ_BUILD.log" 2>&1; }; then
  tail -30 "$FUZZ_BUILD.log"
  for s in "${sources[@]}"; do junit "$(basename "$s" .cpp)" failed "fuzz build failed, see $FUZZ_BUILD.log"; done
  exit 0
fi

for s in "${sources[@]}"; do
  name=$(basename "$s" .cpp)
  reader=${name#fuzz_}
  work=$(mktemp -d)
  seeds=()
  for d in "$REPO_DIR/test/fuzz/corpus/$reader" "$REPO_DIR/test/fixtures/malformed/$reader"; do
    [ -d "$d" ] && seeds+=("$d")
  done
  log="$FUZZ_BUILD/$name.log"
  (cd "$work" && "$FUZZ_BUILD/$name" -max_total_time="$SECONDS_PER_TARGET" -timeout=10 \
      -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 "$work" "${seeds[@]}" > "$log" 2>&1)
  rc=$?
  execs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' || echo 0)
  if [ $rc -eq 0 ]; then
    echo "fuzz_smoke: $name: ok, $execs runs in ${SECONDS_PER_TARGET}s over ${#seeds[@]} seed dir(s)"
    junit "$name" passed ""
  else
    artifact=$(ls "$work"/crash-* "$work"/timeout-* "$work"/leak-* "$work"/oom-* 2>/dev/null | head -1)
    summary=$(grep -m1 -E 'ERROR: |SUMMARY: ' "$log" || echo "exit $rc")
    echo "fuzz_smoke: $name: FAILED ($summary); log $log; input $artifact"
    [ -n "$artifact" ] && mkdir -p "$FUZZ_BUILD/artifacts" && cp "$artifact" "$FUZZ_BUILD/artifacts/$name-$(basename "$artifact")"
    junit "$name" failed "$summary"
  fi
  rm -rf "$work"
done
