#!/bin/sh
# Builds the seed corpora of the fuzz targets in OUT/<target>/ from
#   - the small hand-written seeds in fuzz/corpus/<target>/ (always),
#   - Debian's assimp-testmodels (/usr/share/assimp/models, when installed),
#   - ../shared/data/ (when present; skipped quietly otherwise).
# An OBJ is packed with the MTL files it names and the small textures those name, a glTF
# with its small external buffers and images, as "@@file NAME" sections (fuzz_support.h).
# Files larger than MAX_BYTES contribute their first HEAD_BYTES only.
# Usage: fuzz/seed-corpus.sh OUT
set -eu
out=${1:?usage: seed-corpus.sh OUT}
here=$(cd "$(dirname "$0")" && pwd)
ASSIMP=${MULTIRAY_ASSIMP_MODELS_DIR:-/usr/share/assimp/models}
SHARED=${MULTIRAY_SHARED_DATA_DIR:-$here/../../shared/data}
MAX_BYTES=131072   # whole files up to this size
HEAD_BYTES=32768   # the head of larger ones
PART_BYTES=65536   # companion files (MTL, buffers, images) up to this size

targets="ply obj gltf glb camera_json camera_render trace cli volume transfer messages viewer sequence assimp"
for t in $targets; do
  mkdir -p "$out/$t"
  cp "$here/corpus/$t/"* "$out/$t/" 2>/dev/null || true
done

size() { wc -c < "$1" | tr -d ' '; }

# emit FILE: the file, or its head when it is large.
emit() {
  if [ "$(size "$1")" -le $MAX_BYTES ]; then cat "$1"; else head -c $HEAD_BYTES "$1"; fi
}

# part DIR NAME: appends a "@@file" section for DIR/NAME when it is a small file.
part() {
  f="$1/$2"
  [ -f "$f" ] || return 0
  [ "$(size "$f")" -le $PART_BYTES ] || return 0
  printf '\n@@file %s\n' "$(basename "$2")"
  cat "$f"
}

# seed_name PREFIX FILE: a flat, unique file name for a seed.
seed_name() { printf '%s-%s' "$1" "$(printf '%s' "$2" | tr -c 'A-Za-z0-9._-' '_')"; }

add_obj() {  # add_obj PREFIX ROOT FILE
  dir=$(dirname "$3")
  dest="$out/obj/$(seed_name "$1" "${3#"$2"/}")"
  {
    emit "$3"
    sed -n 's/^[[:space:]]*mtllib[[:space:]]\{1,\}//p' "$3" | tr -d '\r' | head -n 4 |
      while IFS= read -r mtl; do
        part "$dir" "$mtl"
        [ -f "$dir/$mtl" ] || continue
        sed -n 's/^[[:space:]]*map_Kd[[:space:]]\{1,\}//p' "$dir/$mtl" | tr -d '\r' | sort -u |
          head -n 4 | while IFS= read -r tex; do part "$dir" "$tex"; done
      done
  } > "$dest"
}

add_gltf() {  # add_gltf PREFIX ROOT FILE
  dir=$(dirname "$3")
  dest="$out/gltf/$(seed_name "$1" "${3#"$2"/}")"
  {
    emit "$3"
    grep -o '"uri"[[:space:]]*:[[:space:]]*"[^"]*"' "$3" | sed 's/.*"\([^"]*\)"$/\1/' |
      grep -v '^data:' | sort -u | head -n 8 | while IFS= read -r uri; do part "$dir" "$uri"; done
  } > "$dest"
}

add_plain() {  # add_plain TARGET PREFIX ROOT FILE
  emit "$4" > "$out/$1/$(seed_name "$2" "${4#"$3"/}")"
}

# kAssimpExtensions (src/scene/loaders.h), in its order: fuzz_assimp reads the first byte
# of an input as an index into it.
assimp_exts=".3ds .3mf .ac .ase .b3d .blend .cob .dae .dxf .fbx .ifc .lwo .lxo .md2 .ms3d .off \
.q3o .q3s .smd .stl .x .x3d"

add_assimp() {  # add_assimp PREFIX ROOT FILE: its extension's index as a byte, then the file
  ext=.$(printf '%s' "${3##*.}" | tr '[:upper:]' '[:lower:]')
  i=0
  for e in $assimp_exts; do
    if [ "$e" = "$ext" ]; then
      # shellcheck disable=SC2059  # the format is the octal escape of the index
      { printf "\\$(printf '%03o' $i)"; emit "$3"; } > "$out/assimp/$(seed_name "$1" "${3#"$2"/}")"
      return 0
    fi
    i=$((i + 1))
  done
}

# from PREFIX ROOT: every scene file under ROOT.
from() {
  [ -d "$2" ] || return 0
  find "$2" -type f -iname '*.ply' | while IFS= read -r f; do add_plain ply "$1" "$2" "$f"; done
  find "$2" -type f -iname '*.obj' | while IFS= read -r f; do add_obj "$1" "$2" "$f"; done
  find "$2" -type f -iname '*.gltf' | while IFS= read -r f; do add_gltf "$1" "$2" "$f"; done
  find "$2" -type f -iname '*.glb' | while IFS= read -r f; do add_plain glb "$1" "$2" "$f"; done
  find "$2" -type f -iname '*.trace' | while IFS= read -r f; do add_plain trace "$1" "$2" "$f"; done
  find "$2" -type f -iname '*.nhdr' | while IFS= read -r f; do add_plain volume "$1" "$2" "$f"; done
  find "$2" -type f -size -512k | while IFS= read -r f; do add_assimp "$1" "$2" "$f"; done
}

from assimp "$ASSIMP"
from shared "$SHARED"

summary=""
for t in $targets; do summary="$summary $t:$(ls "$out/$t" | wc -l)"; done
echo "fuzz: seed corpora in $out ($summary )"
