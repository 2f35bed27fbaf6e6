#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time from its seed corpus; new
# inputs go to a scratch corpus (the committed one is only read), a crash,
# leak or timeout input to ./fuzz-artifacts/ for reproduction:
#   path/to/fuzz_<name> fuzz-artifacts/crash-...
# Usage: run_fuzzer.sh path/to/fuzz_<name> seed_corpus_dir seconds [random_seed]
# (random_seed 0: a new one each run; CI passes a fixed one, so that a run
# that passes here passes there, and a longer run explores at random.)
set -euo pipefail
fuzzer="$1" seeds="$2" seconds="$3" random_seed="${4:-0}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p fuzz-artifacts
# Leaks are looked for once, at the end, over everything the run left
# (-detect_leaks=0 turns off only libFuzzer's check after each input, a full
# scan each time a library loses memory on an error path).
"$fuzzer" "$scratch" "$seeds" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -detect_leaks=0 \
  -print_final_stats=1 -seed="$random_seed" -artifact_prefix="$PWD/fuzz-artifacts/$(basename "$fuzzer")-"
