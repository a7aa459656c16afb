#!/usr/bin/env bash
# Build the libFuzzer harnesses (clang, ASan + UBSan) and run each for a bounded time.
#   bench/fuzz/run.sh [SECONDS_PER_HARNESS] [HARNESS...]     (default: 300 s; all harnesses)
#   FUZZ_RUNS=1000000 bench/fuzz/run.sh 0 image                (stop after 10^6 executions; 0 s: no time limit)
#   FUZZ_CHUNK=N: at most N executions per process (default: 100000 for image, else no limit)
# The environment passes through: PELLUCID_SIMD=scalar picks the scalar path kernel for the scene
# harnesses' renders (see bench/fuzz/README.md, "Results").
# Harnesses: json mitsuba_xml obj ply image, and load_dict (a Python mutation loop over
# pellucid.load_dict, bench/fuzz/fuzz_load_dict.py, run with the venv's Python if it exists).
# Installs clang and libFuzzer (Debian: clang, libclang-rt-14-dev) when missing. Builds in
# build/fuzz; each harness's corpus grows in build/fuzz/corpus/<harness> (seeded from
# bench/fuzz/corpus/<harness>), crashes land in build/fuzz/crashes/<harness>/, its log in
# build/fuzz/<harness>.log, and one summary line per harness run (time, executions, coverage,
# crashes) is appended to build/fuzz/summary.txt. Exit status 1 if any harness crashed.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
SECONDS_EACH=${1:-300}
shift || true
HARNESSES=("$@")
# FUZZ_RUNS: stop each harness after this many executions (or SECONDS, whichever comes first;
# SECONDS_PER_HARNESS 0 means no time limit). Unset or 0: no execution limit.
RUNS=${FUZZ_RUNS:-0}
[ ${#HARNESSES[@]} -gt 0 ] || HARNESSES=(json mitsuba_xml obj ply image load_dict)
BUILD=$ROOT/build/fuzz

missing=$(for p in clang libclang-rt-14-dev; do dpkg -s $p >/dev/null 2>&1 || echo $p; done)
if [ -n "$missing" ]; then
  SUDO=$( [ "$(id -u)" = 0 ] || echo sudo )
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
fi

CMAKE=cmake; [ -x "$ROOT/.venv/bin/cmake" ] && CMAKE=$ROOT/.venv/bin/cmake
GEN=(); [ -x "$ROOT/.venv/bin/ninja" ] && GEN=(-G Ninja -DCMAKE_MAKE_PROGRAM="$ROOT/.venv/bin/ninja")
native=()
for h in "${HARNESSES[@]}"; do [ "$h" = load_dict ] || native+=("fuzz_$h"); done
if [ ${#native[@]} -gt 0 ]; then
  "$CMAKE" -S bench/fuzz -B "$BUILD" "${GEN[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" >/dev/null
  "$CMAKE" --build "$BUILD" -j"$(nproc)" --target "${native[@]}"
fi

# Inputs are written to files for the readers: on a RAM file system where there is one.
TMP_ROOT=$BUILD/tmp
if [ -d /dev/shm ] && [ -w /dev/shm ]; then TMP_ROOT=$(mktemp -d /dev/shm/pellucid-fuzz-XXXXXX); fi
# The texture cache holds the tiles of every image the harness opened (a scene has a few; the
# harness, thousands): at its default of 2 GB, plus ASan's own overhead, it alone would reach the
# 4 GB memory limit below.
# PELLUCID_MAX_TEXTURE_PIXELS: at the default limit (2^26 pixels) a header of a few bytes makes the
# reader decode and the texel scan read up to 67 M pixels, seconds and about 3 GB per input, which
# dominated the image harness (under 30 inputs per second); at 2^20 every input is decoded in
# milliseconds, and the limit's check from the header is exercised either way.
export TMPDIR=$TMP_ROOT PELLUCID_TEXTURE_CACHE=$TMP_ROOT/texture-cache PELLUCID_TEXTURE_CACHE_MB=256
export PELLUCID_MAX_TEXTURE_PIXELS=${PELLUCID_MAX_TEXTURE_PIXELS:-1048576}
export ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p "$TMPDIR"
status=0
for h in "${HARNESSES[@]}"; do
  mkdir -p "$BUILD/corpus/$h" "$BUILD/crashes/$h"
  log=$BUILD/$h.log
  if [ "$h" = load_dict ]; then
    PY=python3; [ -x "$ROOT/.venv/bin/python" ] && PY=$ROOT/.venv/bin/python
    "$PY" bench/fuzz/fuzz_load_dict.py --seconds "$SECONDS_EACH" --runs "$RUNS" --crashes "$BUILD/crashes/$h" \
      >"$log" 2>&1 || status=1
    echo "$(date -u +%FT%TZ) $h: $(tail -n 1 "$log")" | tee -a "$BUILD/summary.txt"
    continue
  fi
  # -rss_limit_mb: an input that needs more memory is a finding (the limits keep every input far
  # below it). -timeout: an input that takes longer is one too; 60 s for images, whose readers
  # (OpenImageIO's Exif parser, OpenEXR) take up to 10 s under the sanitizers for some inputs.
  # -max_len: the image harness's seeds are under 1.5 KB, and a longer input mostly costs decoding
  # time in the image reader; the scene seeds are up to 5.5 KB. -detect_leaks=0: leaks are not
  # looked for (ASAN_OPTIONS below), so libFuzzer need not run an input twice to check for them.
  maxlen=16384 timeout=20
  [ "$h" = image ] && maxlen=4096 timeout=60
  # The image harness runs its executions in processes of at most 100,000 each (FUZZ_CHUNK): a
  # process keeps the peak memory of the largest images it decoded (the allocator does not return
  # it), so a fresh process per chunk (the corpus carries over) bounds how much of it piles up.
  chunk=${FUZZ_CHUNK:-0}
  [ "$h" = image ] && [ -z "${FUZZ_CHUNK:-}" ] && chunk=100000
  : >"$log"
  marker=$(mktemp); start_s=$(date +%s)
  left=$RUNS execs=0
  while :; do
    limits=(); [ "$SECONDS_EACH" = 0 ] || limits+=(-max_total_time="$SECONDS_EACH")
    this=$left; [ "$chunk" != 0 ] && [ "$left" != 0 ] && [ "$left" -gt "$chunk" ] && this=$chunk
    [ "$this" = 0 ] || limits+=(-runs="$this")
    ok=1
    "$BUILD/fuzz_$h" "$BUILD/corpus/$h" "bench/fuzz/corpus/$h" "${limits[@]}" \
      -rss_limit_mb=4096 -timeout=$timeout -max_len=$maxlen -detect_leaks=0 -print_final_stats=1 \
      -artifact_prefix="$BUILD/crashes/$h/" >>"$log" 2>&1 || { ok=0; status=1; }
    n=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$' || echo 0)
    execs=$((execs + n))
    [ "$ok" = 1 ] && [ "$this" != 0 ] && [ "$this" != "$left" ] || break
    left=$((left - this))
  done
  rate=$(grep -o 'exec/s: *[0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -n 1 || echo 'cov: ?')
  # Findings of this run only (crash-, oom-, timeout-, leak- files; libFuzzer's slow-unit reports
  # are not findings).
  crashes=$(find "$BUILD/crashes/$h" -type f -newer "$marker" \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' -o -name 'leak-*' \) | wc -l)
  rm -f "$marker"
  secs=$(( $(date +%s) - start_s ))
  echo "$(date -u +%FT%TZ) $h: $execs executions in $secs s ($rate exec/s), $cov, $crashes crashes" \
    | tee -a "$BUILD/summary.txt"
done
rm -rf "$TMPDIR"
exit $status
