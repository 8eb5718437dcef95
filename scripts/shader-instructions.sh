#!/usr/bin/env bash
# Counts the instructions that lavapipe's compiled shaders execute while `argil render`
# draws one frame of each scene: valgrind's callgrind counts every instruction, and the
# shaders are the code that LLVM compiled at run time, which belongs to no file. Unlike
# `argil bench`'s times, the count is the same however loaded the machine is (within
# 0.01% between runs), so two variants of a scene, or two builds of the shaders, can be
# compared on a busy machine: their difference is what the variant costs to shade.
#
#   scripts/shader-instructions.sh [--size WxH] [--frames N] [--argil PATH] [--by-shader] SCENE.toml...
#
# Prints one line per scene: its shader instructions and the whole process's. With
# --by-shader, each run-time compiled shader that lavapipe's rasterizer or compute code
# calls follows, by its address: its instructions with the functions it calls (texture
# lookups) and its calls. A fragment shader is called once per 4×4 block of pixels for
# each triangle that covers any of them, so calls × 16 against an object's pixels says how
# often its pixels are shaded; a pipeline's address changes with the build, so tell the
# objects apart by a variant of the scene. The shader count covers every pass of the frame (shadow maps, forward, skybox, tone map) and the
# environment precompute where the disk cache does not hold it. With --frames N, N frames
# are drawn (accumulated, as `argil render --accumulate N`): what is computed once per
# scene (shadow maps, the ground's maps) counts once, so the difference of the counts at
# N = 2 and N = 1 is a steady frame's. Needs valgrind (Debian:
# apt install valgrind); each scene takes about 3 minutes at the default 320×180.
set -euo pipefail

size=320x180
frames=1
argil="$(dirname "$0")/../target/release/argil"
by_shader=0
while [ $# -gt 0 ]; do
  case "$1" in
    --size) size="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --argil) argil="$2"; shift 2 ;;
    --by-shader) by_shader=1; shift ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
if [ $# -eq 0 ]; then
  echo "usage: $0 [--size WxH] [--frames N] [--argil PATH] [--by-shader] SCENE.toml..." >&2
  exit 2
fi
command -v valgrind >/dev/null || { echo "$0: needs valgrind (apt install valgrind)" >&2; exit 1; }
[ -x "$argil" ] || { echo "$0: no argil at $argil (cargo build --release)" >&2; exit 1; }

for scene in "$@"; do
  [ -f "$scene" ] || { echo "$0: $scene: no such file" >&2; exit 2; }
done

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf '%-40s %18s %18s\n' scene shader_instructions all_instructions
for scene in "$@"; do
  valgrind --tool=callgrind --callgrind-out-file="$work/out" \
    "$argil" render "$scene" --width "${size%x*}" --height "${size#*x}" --accumulate "$frames" \
    --out "$work/frame.exr" --overwrite \
    >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
  # Functions of no object file ([???]) are the run-time compiled shaders.
  shaders=$(callgrind_annotate --inclusive=no --threshold=100 "$work/out" |
    awk '/\[\?\?\?\]$/ { gsub(",", "", $1); s += $1 } END { printf "%.0f", s }')
  all=$(awk '/^summary:/ { print $2 }' "$work/out")
  printf '%-40s %18s %18s\n' "$scene" "$shaders" "$all"
  if [ "$by_shader" = 1 ]; then
    # A run-time compiled function ([???]) that libvulkan_lvp calls is a shader's entry;
    # its callers' lines, above it, give the calls.
    callgrind_annotate --inclusive=yes --tree=caller --threshold=100 "$work/out" | awk '
      /< .*libvulkan_lvp\.so\]$/ { n = $0; sub(/.*\(/, "", n); sub(/x\).*/, "", n); gsub(",", "", n); calls += n; next }
      /\*  \?\?\?:0x[0-9a-f]+ \[\?\?\?\]$/ {
        if (calls > 0) { ir = $1; gsub(",", "", ir); printf "  shader %s %18d instructions %10d calls\n", $(NF - 1), ir, calls }
        calls = 0; next }
      /^$/ { calls = 0 }' | sort -k3 -n -r
  fi
done
