#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz (clang, ASan + UBSan) and runs
# each for SECONDS (default 60), PARALLEL at a time.
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. bash scripts/fuzz.sh 1800
# Environment: BUILD_DIR (default build-fuzz), JOBS (build jobs, default 1),
# PARALLEL (targets fuzzed at once, default 1; each uses one core),
# FUZZ_SEED (libFuzzer's -seed; default: from the clock; CI fixes it),
# LIGHTBENCH_FUZZ_STRICT (default 1: for scene/experiment, an exception that is
# not a ConfigError, i.e. a message without file:line:key, is a finding; 0
# counts only crashes, hangs, leaks and sanitizer reports). Findings go to
# BUILD_DIR/fuzz-artifacts/TARGET/; the grown corpus stays in
# BUILD_DIR/fuzz-corpus/TARGET/ for the next run. Exits 1 if any target has
# findings.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
SECONDS_PER_TARGET=${1:-60}
shift || true
ALL_TARGETS=(fuzz_scene fuzz_mitsuba fuzz_pbrt fuzz_experiment fuzz_mesh fuzz_exr fuzz_texture)
if (($#)); then TARGETS=("$@"); else TARGETS=("${ALL_TARGETS[@]}"); fi
BUILD=${BUILD_DIR:-$ROOT/build-fuzz}
JOBS=${JOBS:-1}
# UBSan stacks in reports (it already aborts: -fno-sanitize-recover); short
# dedup tokens let fork mode tell repeated crashes apart.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
export ASAN_OPTIONS=${ASAN_OPTIONS:-dedup_token_length=3}
export LIGHTBENCH_FUZZ_STRICT=${LIGHTBENCH_FUZZ_STRICT:-1}
SEED_FLAG=()
[[ -n "${FUZZ_SEED:-}" ]] && SEED_FLAG=(-seed="$FUZZ_SEED")

# Inputs larger than this are truncated: enough for any seed scene or
# experiment, small enough that a fuzzer cannot spell out a huge mesh.
declare -A MAX_LEN=([fuzz_scene]=8192 [fuzz_mitsuba]=16384 [fuzz_pbrt]=16384 [fuzz_experiment]=8192 [fuzz_mesh]=16384 [fuzz_exr]=16384 [fuzz_texture]=16384)

for t in "${TARGETS[@]}"; do
  [[ -n "${MAX_LEN[$t]:-}" ]] || { echo "fuzz: unknown target '$t' (have: ${ALL_TARGETS[*]})" >&2; exit 2; }
done

echo "fuzz: building in $BUILD (clang, -j$JOBS)"
mkdir -p "$BUILD"
CC=clang CXX=clang++ cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DLIGHTBENCH_FUZZ=ON -DLIGHTBENCH_TESTS=OFF -DLIGHTBENCH_PYTHON=OFF >"$BUILD/fuzz-configure.log" 2>&1 ||
  { cat "$BUILD/fuzz-configure.log" >&2; exit 2; }
cmake --build "$BUILD" -j"$JOBS" --target "${TARGETS[@]}" fuzz_exr_seeds >"$BUILD/fuzz-build.log" 2>&1 ||
  { tail -40 "$BUILD/fuzz-build.log" >&2; exit 2; }
BIN=$BUILD/tests/fuzz

# Seeds: whatever exists of scenes/, experiments/, tests/data/.
seed_files() {
  case $1 in
    fuzz_scene) find scenes tests/data -name '*.yaml' 2>/dev/null || true ;;
    fuzz_mitsuba) find scenes tests/data -name '*.xml' 2>/dev/null || true ;;
    fuzz_pbrt) find scenes tests/data -name '*.pbrt' -size -16k 2>/dev/null || true ;;
    fuzz_experiment) find experiments tests/data -name '*.yaml' 2>/dev/null || true ;;
    fuzz_mesh) find scenes/meshes tests/data \( -name '*.obj' -o -name '*.ply' \) 2>/dev/null || true ;;
    fuzz_exr) find tests/data -name '*.exr' 2>/dev/null || true ;;
    fuzz_texture) find scenes tests/data \( -name '*.exr' -o -name '*.png' \) -size -64k 2>/dev/null || true ;;
  esac
}
make_seeds() {
  local t=$1 dir=$BUILD/fuzz-seeds/$1
  rm -rf "$dir" && mkdir -p "$dir"
  local f
  while read -r f; do
    [[ -n "$f" ]] || continue
    local name=${f//\//_}
    if [[ $t == fuzz_mesh ]]; then
      # fuzz_mesh's first byte: bit 0 = PLY, bit 1 = smooth normals.
      local ext=0; [[ $f == *.ply ]] && ext=1
      printf "\\x0$ext" | cat - "$f" >"$dir/$name"
      printf "\\x0$((ext + 2))" | cat - "$f" >"$dir/$name.smooth"
    else
      cp "$f" "$dir/$name"
    fi
  done < <(seed_files "$t")
  [[ $t == fuzz_exr ]] && "$BIN/fuzz_exr_seeds" "$dir"
  if [[ $t == fuzz_texture ]]; then
    # fuzz_texture's first byte picks the use (see fuzz_texture.cpp): each
    # image as a PNG or EXR texture and as an environment map.
    local tmp=$BUILD/fuzz-seeds/texture-images
    rm -rf "$tmp" && mkdir -p "$tmp" && "$BIN/fuzz_exr_seeds" "$tmp"
    for f in "$dir"/* "$tmp"/*; do
      [[ -f "$f" ]] || continue
      if [[ $f == *.png ]]; then printf '\x02' | cat - "$f" >"$f.tex" && printf '\x06' | cat - "$f" >"$f.srgb"
      else printf '\x00' | cat - "$f" >"$f.tex" && printf '\x01' | cat - "$f" >"$f.env" && printf '\x03' | cat - "$f" >"$f.uniform"; fi
      rm "$f"
    done
    mv "$tmp"/* "$dir"/ 2>/dev/null || true
  fi
  if [[ $t == fuzz_mesh ]]; then
    # The repo has no PLY (nor OBJ with normals and uvs): small ones so the
    # fuzzer starts inside both readers. First byte as above.
    local tri='element face 1\nproperty list uchar int vertex_indices\nend_header\n'
    printf '\x01ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n'"$tri"'0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$dir/gen-ascii.ply"
    { printf '\x03ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n'"$tri"
      printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0'
      printf '\x03\0\0\0\0\x01\0\0\0\x02\0\0\0'; } >"$dir/gen-binary.ply"
    printf '\x00v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf -3 -2 -1\nf 1 2 3 4\n' >"$dir/gen-uv-normals.obj"
  fi
  return 0
}

# A finding's signature: the first report line (an assertion, our harness's
# message, the sanitizer's summary), numbers masked (pids, sizes, YAML
# line/column), plus the top two frames outside the runtimes and the first
# frame inside the project. Equal signatures are the same finding.
signature() {
  local t=$1 input=$2 out summary top project
  out=$(timeout 60 "$BIN/$t" -timeout=10 -rss_limit_mb=2048 "$input" 2>&1 | tr -d '\000' || true)
  summary=$(grep -a -m1 -E 'Assertion `|^fuzz: |^SUMMARY:|ERROR: libFuzzer' <<<"$out" |
            sed -E 's/==[0-9]+== ?//; /^SUMMARY/ s/ \([^)]*\)//g; s/^.*\/([^/]+:[0-9]+): .*(Assertion .*)$/\1: \2/
                    s/[0-9]+/N/g' | cut -c1-110)
  frames() { grep -a -E '^ +#[0-9]+ 0x[0-9a-f]+ in ' <<<"$out" | sed -E 's/^ +#[0-9]+ 0x[0-9a-f]+ in //'; }
  top=$(frames | grep -v -E '__sanitizer|__asan|__ubsan|fuzzer::|libc\.so|nptl/|stdlib/|assert/|signal/|tests/fuzz/|^_start|^main |csu/|sysdeps/|libio/|^__GI|^_IO_|^std::|libstdc' |
        head -2 | sed -E 's/\(.*//' | paste -sd';')
  project=$(frames | grep -F "$ROOT/" | grep -v tests/fuzz/ | head -1 | awk '{f=$1; sub(/\(.*/, "", f); print f " " $NF}' |
            sed "s|$ROOT/||g")
  echo "${summary:-no report on rerun} @ ${top:-?} < ${project:-no project frame}"
}

# One target's run; its table row (and findings) go to fuzz-logs/TARGET.row,
# a file TARGET.found marks findings.
run_target() {
  local t=$1
  make_seeds "$t"
  local corpus=$BUILD/fuzz-corpus/$t artifacts=$BUILD/fuzz-artifacts/$t log=$BUILD/fuzz-logs/$t.log
  local row=$BUILD/fuzz-logs/$t.row
  # The targets' temp folders (and libFuzzer's fork folder) go here: a process
  # that crashes or is stopped at the time limit skips its atexit clean-up.
  export TMPDIR=$BUILD/fuzz-tmp/$t
  rm -rf "$TMPDIR" "$BUILD/fuzz-logs/$t.found"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")" "$TMPDIR"
  # -fork=1 with -ignore_*: one worker that carries on after a finding, so
  # one run collects several. -close_fd_mask=3 hides the loaders' warnings;
  # sanitizer reports still reach the log.
  "$BIN/$t" "$corpus" "$BUILD/fuzz-seeds/$t" "${SEED_FLAG[@]}" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 \
    -max_total_time="$SECONDS_PER_TARGET" -max_len="${MAX_LEN[$t]}" -rss_limit_mb=2048 -timeout=10 \
    -close_fd_mask=3 -artifact_prefix="$artifacts/" >"$log" 2>&1 || true
  # Fork mode's status lines: "#RUNS: cov: .. corp: N exec/s: E oom/timeout/crash: ..".
  local last execs rate ncorpus
  last=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1 || true)
  execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$last")
  rate=$(sed -nE 's/.*exec\/s:? ([0-9]+).*/\1/p' <<<"$last")
  # The corpus in use (seeds + what this and earlier runs added to $corpus).
  ncorpus=$(sed -nE 's/.*corp: ([0-9]+).*/\1/p' <<<"$last")
  mapfile -t found < <(find "$artifacts" -type f \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' \
                         -o -name 'leak-*' -o -name 'slow-unit-*' \) | sort)
  printf '%-16s %10s %8s %8s %9s\n' "$t" "${execs:-?}" "${rate:-?}" "${ncorpus:-?}" "${#found[@]}" >"$row"
  if ((${#found[@]})); then
    touch "$BUILD/fuzz-logs/$t.found"
    # Distinct findings (artifacts of earlier runs included), with one example each.
    for f in "${found[@]:0:40}"; do echo "$(signature "$t" "$f")|$f"; done | sort -t'|' -k1,1 -u |
      while IFS='|' read -r sig f; do echo "    $sig"; echo "      e.g. $f"; done >>"$row"
  fi
  rm -rf "$TMPDIR"
}

# PARALLEL targets at a time (default 1). Each libFuzzer run has one worker,
# so on 2 cores CI runs two at once: every target still gets its full
# SECONDS_PER_TARGET of one core, in half the wall time.
PARALLEL=${PARALLEL:-1}
mkdir -p "$BUILD/fuzz-logs"
running=0
for t in "${TARGETS[@]}"; do
  if ((running >= PARALLEL)); then wait -n || true; running=$((running - 1)); fi
  run_target "$t" &
  running=$((running + 1))
done
wait

status=0
printf '\n%-16s %10s %8s %8s %9s\n' target execs exec/s corpus findings
for t in "${TARGETS[@]}"; do
  cat "$BUILD/fuzz-logs/$t.row" 2>/dev/null || { printf '%-16s did not report\n' "$t"; status=1; }
  [[ -e "$BUILD/fuzz-logs/$t.found" ]] && status=1
done
echo
echo "logs: $BUILD/fuzz-logs/  reproduce: $BIN/TARGET ARTIFACT"
exit $status
