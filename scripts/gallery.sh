#!/bin/sh
# Renders docs/gallery/: every scene of ../shared/data/meshes and the Cornell boxes with
# default options (the volumes too), then Sponza, the helmets and the aneurism with a
# chosen camera (the README's, where it has one), at 480x270.
# Usage: scripts/gallery.sh [BUILD_DIR] [SPP]   (defaults: build, 64)
#        ONLY="aneurism-close damaged-helmet-close" scripts/gallery.sh   (just those)
set -eu
cd "$(dirname "$0")/.."
BUILD=${1:-build}
SPP=${2:-64}
BIN=$BUILD/src/app/multiray
DATA=../shared/data
OUT=docs/gallery
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
[ -x "$BIN" ] || { echo "gallery: build first ($BIN missing)" >&2; exit 1; }
[ -d "$DATA/meshes" ] || { echo "gallery: needs $DATA (see its README)" >&2; exit 1; }
mkdir -p "$OUT"

# name | scene (empty: built-in) | extra options
render() {
  name=$1; scene=$2; shift 2
  case " ${ONLY:-$name} " in *" $name "*) ;; *) return 0 ;; esac
  echo "gallery: $name"
  # shellcheck disable=SC2086
  "$BIN" render $scene --res "$RES" --spp "$SPP" --out "$TMP/$name" --quiet "$@" \
    > "$TMP/$name.log" 2>&1 || { cat "$TMP/$name.log" >&2; exit 1; }
  cp "$TMP/$name/frame_0000.png" "$OUT/$name.png"
}

RES=480x270
render default ""
render cornell-mcguire "$DATA/cornell_box/mcguire/CornellBox-Original.obj"
RES=270x270  # the file's own square film
render cornell-mitsuba "$DATA/cornell_box/mitsuba/docs/scenes/variants_cbox_rgb.xml" \
  --allow-outside-paths
RES=480x270
render bunny "$DATA/meshes/stanford_bunny/bunny.ply"
render damaged-helmet "$DATA/meshes/damaged_helmet/DamagedHelmet.gltf"
render flight-helmet "$DATA/meshes/flight_helmet/FlightHelmet.gltf"
render flight-helmet-notextures "$DATA/meshes/flight_helmet/FlightHelmet_notextures.gltf"
render sponza "$DATA/meshes/dabrovic_sponza/sponza.obj"
render engine "$DATA/meshes/assimp/2CylinderEngine.glb"
render clearcoat "$DATA/meshes/assimp/ClearCoatTest/ClearCoatTest.gltf"
render wuson-obj "$DATA/meshes/assimp/WusonOBJ.obj"
render wuson-ply "$DATA/meshes/assimp/Wuson.ply"
render regr01 "$DATA/meshes/assimp/regr01.obj"
render aneurism "$DATA/volumes/aneurism_256x256x256_uint8.nhdr"
render cranium "$DATA/volumes/cranium_ct_256x256x108_int16le.nhdr"
render neghip "$DATA/volumes/neghip_64x64x64_uint8.nhdr"

# Chosen cameras (eye, target, up, vertical fov).
render engine-framed "$DATA/meshes/assimp/2CylinderEngine.glb" --camera default
render sponza-hall "$DATA/meshes/dabrovic_sponza/sponza.obj" \
  --camera -11,3.5,0.5,10,6,-0.5,0,1,0,65 --env 1 --sun 30,70,4
render sponza-hall-ev4 "$DATA/meshes/dabrovic_sponza/sponza.obj" \
  --camera -10,3,0,10,5,0,0,1,0,60 --exposure 4 --tone filmic  # the README's hall
render damaged-helmet-close "$DATA/meshes/damaged_helmet/DamagedHelmet.gltf" \
  --camera 1.15,0.1,3.45,0,-0.2,0,0,1,0,38 --env 0.6 --sun 40,45,3
render aneurism-close "$DATA/volumes/aneurism_256x256x256_uint8.nhdr" --tf angio \
  --camera -215,308,158,0,0,-17,0,0,1,45
render flight-helmet-close "$DATA/meshes/flight_helmet/FlightHelmet_notextures.gltf" \
  --camera 0.9,0.25,0.2,0,0.05,0,0,1,0,36 --env 0.5 --sun 40,45,3
echo "gallery: wrote $OUT/${ONLY:+ ($ONLY)}"
