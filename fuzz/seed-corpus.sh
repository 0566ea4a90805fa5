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

# Every file costs one process at most (cat or head; an OBJ or glTF a few more for its
# companions): starting a process takes 10-25 ms on a loaded two-core machine, and this
# runs inside `make test` (FuzzReplay.seeds) over about 600 files.

# list ROOT FIND-TESTS...: a line "SIZE<tab>PATH<tab>NAME" for every file under ROOT the
# tests select, NAME being its path below ROOT with each byte outside [A-Za-z0-9._-]
# made '_' (a flat, unique seed name).
list() {
  root=$1
  shift
  find "$root" -type f "$@" -printf '%s\t%p\t%P\n' |
    LC_ALL=C awk -F '\t' '{ n = $3; gsub(/[^A-Za-z0-9._-]/, "_", n); print $1 "\t" $2 "\t" n }'
}

# emit SIZE FILE: the file, or its head when it is large.
emit() {
  if [ "$1" -le $MAX_BYTES ]; then cat "$2"; else head -c $HEAD_BYTES "$2"; fi
}

# parts DIR: for each name read (one a line), a "@@file" section for DIR/NAME when it is a
# small file.
parts() {
  while IFS= read -r name; do
    f="$1/$name"
    [ -f "$f" ] || continue
    [ "$(wc -c < "$f")" -le $PART_BYTES ] || continue
    printf '\n@@file %s\n' "${name##*/}"
    cat "$f"
  done
}

add_obj() {  # add_obj PREFIX SIZE FILE NAME: with its MTL files (4) and their textures (4 each)
  dir=${3%/*}
  {
    emit "$2" "$3"
    sed -n 's/^[[:space:]]*mtllib[[:space:]]\{1,\}//; T; s/\r//g; p' "$3" | head -n 4 |
      while IFS= read -r mtl; do
        printf '%s\n' "$mtl" | parts "$dir"
        [ -f "$dir/$mtl" ] || continue
        sed -n 's/^[[:space:]]*map_Kd[[:space:]]\{1,\}//; T; s/\r//g; p' "$dir/$mtl" | sort -u |
          head -n 4 | parts "$dir"
      done
  } > "$out/obj/$1-$4"
}

add_gltf() {  # add_gltf PREFIX SIZE FILE NAME: with its external buffers and images (8)
  {
    emit "$2" "$3"
    grep -o '"uri"[[:space:]]*:[[:space:]]*"[^"]*"' "$3" |
      sed -e 's/.*"\([^"]*\)"$/\1/' -e '/^data:/d' | sort -u | head -n 8 | parts "${3%/*}"
  } > "$out/gltf/$1-$4"
}

# kAssimpExtensions (src/scene/loaders.h), in its order: fuzz_assimp reads the first byte
# of an input as an index into it.
assimp_exts=".3ds .3mf .ac .ase .b3d .blend .cob .dae .dxf .fbx .ifc .lwo .lxo .md2 .ms3d .off \
.q3o .q3s .smd .stl .x .x3d"

# from PREFIX ROOT: every scene file under ROOT.
from() {
  [ -d "$2" ] || return 0
  tab=$(printf '\t')
  for t in ply glb trace; do
    list "$2" -iname "*.$t" | while IFS=$tab read -r size f name; do
      emit "$size" "$f" > "$out/$t/$1-$name"
    done
  done
  list "$2" -iname '*.nhdr' | while IFS=$tab read -r size f name; do
    emit "$size" "$f" > "$out/volume/$1-$name"
  done
  list "$2" -iname '*.obj' | while IFS=$tab read -r size f name; do
    add_obj "$1" "$size" "$f" "$name"
  done
  list "$2" -iname '*.gltf' | while IFS=$tab read -r size f name; do
    add_gltf "$1" "$size" "$f" "$name"
  done
  # Files under 512 KB of the formats fuzz_assimp reads, its extension's index as a byte first.
  i=0
  for e in $assimp_exts; do
    byte=$(printf '%03o' $i)
    list "$2" -size -512k -iname "*$e" | while IFS=$tab read -r size f name; do
      # shellcheck disable=SC2059  # the format is the octal escape of the index
      { printf "\\$byte"; emit "$size" "$f"; } > "$out/assimp/$1-$name"
    done
    i=$((i + 1))
  done
}

from assimp "$ASSIMP"
from shared "$SHARED"

summary=""
for t in $targets; do summary="$summary $t:$(ls "$out/$t" | wc -l)"; done
echo "fuzz: seed corpora in $out ($summary )"
