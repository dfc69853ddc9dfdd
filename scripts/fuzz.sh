#!/usr/bin/env bash
# Fuzzes the scene parser, the OBJ/PLY/STL readers, the checkpoint reader and the command-line parser
# with libFuzzer (docs/fuzzing.md).
#   scripts/fuzz.sh [SECONDS_PER_TARGET]        default 60; FUZZ_TARGETS="scene ply" picks targets
# Installs clang and its libFuzzer runtime when missing (apt-get), builds tests/fuzz in build/fuzz,
# runs each target for SECONDS on a fresh copy of its seed corpus (tests/fuzz/corpus is never
# written), FUZZ_JOBS targets at a time (default: one per core; libFuzzer uses one core), and
# prints a table. Exits 1 when a target crashed, hung, leaked or ran out of memory,
# naming the input that did it; 2 when the tools cannot be installed. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
targets=${FUZZ_TARGETS:-scene obj ply stl checkpoint command_line}
jobs=${FUZZ_JOBS:-$(nproc)}
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "usage: scripts/fuzz.sh [SECONDS_PER_TARGET]  (a whole number >= 1, default 60)" >&2
  exit 2
fi

# ---- Tools: clang++ with the libFuzzer runtime, CMake, Ninja, toml++ --------------------------
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
apt_install() {
  echo "fuzz: installing $*"
  $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}
# Whether clang++ links a libFuzzer target (its runtime's file name differs between versions).
has_fuzzer_runtime() {
  local dir status=0
  dir=$(mktemp -d)
  echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' >"$dir/t.cpp"
  clang++ -fsanitize=fuzzer,address,undefined "$dir/t.cpp" -o "$dir/t" >/dev/null 2>&1 || status=1
  rm -rf "$dir"
  return $status
}
# An apt package that exists in this machine's package lists.
apt_has() { apt-cache policy "$1" 2>/dev/null | grep -q 'Candidate: [0-9]'; }

missing=()
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
command -v ninja >/dev/null 2>&1 || missing+=(ninja-build)
[ -e /usr/include/toml++/toml.h ] || [ -e .deps/include/toml++/toml.h ] || missing+=(libtomlplusplus-dev)
command -v clang++ >/dev/null 2>&1 || missing+=(clang)
if [ ${#missing[@]} -gt 0 ] && ! apt_install "${missing[@]}"; then
  echo "fuzz: could not install ${missing[*]} with apt-get; install them (Debian/Ubuntu names)" \
    "and run again" >&2
  exit 2
fi
if ! has_fuzzer_runtime; then
  # Debian splits the runtime out: libclang-rt-<major>-dev for the default clang's major version
  # (bookworm: 14), or the unversioned libclang-rt-dev.
  major=$(clang++ -dumpversion | cut -d. -f1)
  for package in "libclang-rt-$major-dev" libclang-rt-dev; do
    apt_has "$package" || { $sudo apt-get update -qq >/dev/null 2>&1 || true; }
    if apt_has "$package" && apt_install "$package" && has_fuzzer_runtime; then break; fi
  done
fi
if ! has_fuzzer_runtime; then
  echo "fuzz: clang++ $(clang++ -dumpversion) has no libFuzzer runtime (libclang_rt.fuzzer) and" \
    "libclang-rt-<version>-dev could not be installed; install it and run again" >&2
  exit 2
fi

# ---- Build ------------------------------------------------------------------------------------
cmake -S tests/fuzz -B build/fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build build/fuzz -j "$jobs"

# ---- Run --------------------------------------------------------------------------------------
# ASan/UBSan stop at the first error with a stack; libFuzzer's own limits catch hangs, huge
# allocations and leaks.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:symbolize=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# One target for SECONDS; its exit status goes to $work/status.
fuzz_one() {
  local target=$1 work=build/fuzz/run/$1 dict=tests/fuzz/$1.dict status=0
  [ "$target" = scene ] && dict=tests/fuzz/toml.dict
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts"
  cp tests/fuzz/corpus/"$target"/* "$work/corpus/"
  # New inputs go to the first folder only: the copy. The regression inputs seed it too.
  local seeds=("$work/corpus")
  [ -d "tests/fuzz/regressions/$target" ] && seeds+=("tests/fuzz/regressions/$target")
  build/fuzz/fuzz_"$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -print_final_stats=1 -dict="$dict" -artifact_prefix="$work/artifacts/" "${seeds[@]}" \
    >"$work/fuzz.log" 2>&1 || status=$?
  echo "$status" >"$work/status"
}
running=0
for target in $targets; do
  echo "fuzz: $target for ${seconds} s (log: build/fuzz/run/$target/fuzz.log)"
  fuzz_one "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true

rows=()
failures=()
fuzzed=0
for target in $targets; do
  work=build/fuzz/run/$target
  status=$(cat "$work/status" 2>/dev/null || echo "no status")
  # Final stats (printed twice after a crash): executions and rate from the last stat:: lines,
  # coverage from the last "cov: ... ft: ..." line.
  execs=$(awk '/^stat::number_of_executed_units:/ {v = $2} END {print v}' "$work/fuzz.log")
  rate=$(awk '/^stat::average_exec_per_sec:/ {v = $2} END {print v}' "$work/fuzz.log")
  cov=$(grep -o 'cov: [0-9]*' "$work/fuzz.log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$work/fuzz.log" | tail -1 | cut -d' ' -f2)
  crashes=$(find "$work/artifacts" -type f | wc -l)
  if [ "$status" != 0 ] || [ "$crashes" -gt 0 ]; then
    inputs=$(find "$work/artifacts" -type f | tr '\n' ' ')
    failures+=("$target (exit $status): ${inputs:-no input saved}; see $work/fuzz.log")
    [ "$crashes" -gt 0 ] || crashes=1
  fi
  rows+=("$target ${seconds} ${execs:-0} ${rate:-0} ${cov:-?} ${ft:-?} $crashes")
  fuzzed=$((fuzzed + seconds))
done

# ---- Report -----------------------------------------------------------------------------------
echo
printf '%-8s %8s %12s %9s %7s %7s %8s\n' target seconds execs execs/s cov ft crashes
for row in "${rows[@]}"; do
  # shellcheck disable=SC2086  # the row is split into its columns on purpose
  printf '%-8s %8s %12s %9s %7s %7s %8s\n' $row
done
if [ ${#failures[@]} -gt 0 ]; then
  echo
  for failure in "${failures[@]}"; do echo "fuzz: FAILED $failure" >&2; done
  echo "fuzz: reproduce with build/fuzz/fuzz_<target> <input>;" \
    "keep the input in tests/fuzz/regressions/<target>/" >&2
  exit 1
fi
echo "fuzz: no crash in $fuzzed s of fuzzing"
