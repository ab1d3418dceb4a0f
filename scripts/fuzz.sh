#!/usr/bin/env bash
# Fuzzes the model reader (issue 13): builds ./build-fuzz with clang-14 (libFuzzer, ASan, UBSan;
# -DLATTICEDYN_FUZZ=ON) and runs tests/fuzz/model_reader_fuzzer for SECONDS (default 120) on a
# copy of the corpus tests/fuzz/corpus/model_reader, in an empty temporary directory. Prints the
# number of executions; exits non-zero on any finding (a crash, an ASan or UBSan report, an
# exception other than InputError, a leak, an input over 10 s, an allocation over 2 GiB, a file
# written), whose input is kept in build-fuzz/findings/<time>/.
#   scripts/fuzz.sh [SECONDS] [--merge]
# --merge adds the run's inputs that reach code the corpus does not to tests/fuzz/corpus/ (-merge=1).
# Needs clang-14, libclang-rt-14-dev and libomp-14-dev (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=${1:-120}
merge=${2:-}
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "usage: scripts/fuzz.sh [SECONDS] [--merge]" >&2; exit 2; }
build_dir=$(realpath -m "${LATTICEDYN_FUZZ_DIR:-build-fuzz}")
jobs=${LATTICEDYN_JOBS:-$(nproc)}
corpus=$root/tests/fuzz/corpus/model_reader

for tool in clang-14 clang++-14 cmake; do
  command -v "$tool" >/dev/null || { echo "fuzz.sh: $tool missing (apt-get install clang-14 libclang-rt-14-dev libomp-14-dev)" >&2; exit 1; }
done
[[ -f "$(clang-14 -print-resource-dir)/lib/linux/libclang_rt.fuzzer-$(uname -m).a" ]] ||
  { echo "fuzz.sh: libFuzzer missing (apt-get install libclang-rt-14-dev)" >&2; exit 1; }

cmake -S . -B "$build_dir" -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLATTICEDYN_FUZZ=ON \
      -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -gz -DNDEBUG" \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -gz -DNDEBUG" \
      -DLATTICEDYN_BUILD_TESTS=OFF -DLATTICEDYN_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build_dir" -j "$jobs" --target model_reader_fuzzer
fuzzer=$build_dir/model_reader_fuzzer

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/corpus" "$work/run"
cp "$corpus"/* "$work/corpus/"
findings=$build_dir/findings/$(date +%Y%m%d-%H%M%S)
mkdir -p "$findings"
# The sanitizers' own bookkeeping grows over a long run (about 2 kB an execution; the allocation
# stacks ASan keeps most of it): 10 frames of them, and 4 GiB for the whole process.
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:malloc_context_size=10
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export OMP_NUM_THREADS=1
echo "fuzz.sh: fuzzing the model reader for $seconds s on $(ls "$work/corpus" | wc -l) inputs"
status=0
start=$SECONDS
# The run directory is empty and the working directory: relative paths in a model lead nowhere.
(cd "$work/run" && "$fuzzer" -max_total_time="$seconds" -max_len=16384 -timeout=10 -rss_limit_mb=4096 \
   -malloc_limit_mb=2048 -dict="$root/tests/fuzz/model_reader.dict" -artifact_prefix="$findings/" \
   -print_final_stats=1 "$work/corpus") >"$findings/fuzz.log" 2>&1 || status=$?

executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$findings/fuzz.log" | tail -1)
rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$findings/fuzz.log" | tail -1)
echo "fuzz.sh: ${executions:-?} executions in $((SECONDS - start)) s (${rate:-?} per second)"
if [[ -n "$(ls -A "$work/run")" ]]; then
  echo "fuzz.sh: FINDING: the reader wrote into its working directory: $(ls -A "$work/run")" >&2
  status=1
fi
if ((status == 72)) && grep -q "run interrupted" "$findings/fuzz.log"; then  # SIGINT or SIGTERM
  echo "fuzz.sh: interrupted, no finding up to then" >&2
  exit 130
fi
if ((status != 0)); then
  grep -E "ERROR|SUMMARY|terminate called|what\(\)|Test unit written" "$findings/fuzz.log" >&2 || tail -20 "$findings/fuzz.log" >&2
  echo "fuzz.sh: FINDING (libFuzzer exit $status): input and log in $findings" >&2
  exit 1
fi
if [[ "$merge" == --merge ]]; then
  (cd "$work/run" && "$fuzzer" -merge=1 -max_len=16384 -timeout=10 -rss_limit_mb=4096 "$corpus" "$work/corpus") \
    >"$findings/merge.log" 2>&1
  echo "fuzz.sh: corpus now $(ls "$corpus" | wc -l) inputs, $(du -sh "$corpus" | cut -f1)"
fi
mv "$findings/fuzz.log" "$build_dir/fuzz.log"
rm -rf "$findings"  # nothing found
