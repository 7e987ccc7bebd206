#!/bin/sh
# Rebuilds docs/gallery.png (a montage of example scenes) and
# docs/gallery-compare.png (the two Figure 1 comparisons) with the project's own
# renders. Usage: scenes/gallery.sh [BUILD_DIR]   (default: build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin="$root/${1:-build}/cli/rosyhatch"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tiles=""
for s in bunny armadillo man head mannequin-devil lion-head fandisk couplingdown camel triceratops femur \
         three-peaks torus genus2 fig3-singularities fig4-separatrices; do
    "$bin" render "$root/scenes/$s.yaml" --set 'camera.resolution=[360, 360]' -o "$tmp/$s.png" --quiet >/dev/null
    # Drawings carry alpha, field pictures do not: one channel layout for the mosaic.
    oiiotool "$tmp/$s.png" --ch R,G,B -o "$tmp/$s.png"
    tiles="$tiles $tmp/$s.png"
done
# shellcheck disable=SC2086
oiiotool $tiles --mosaic:pad=0 4x4 -o "$root/docs/gallery.png"
"$bin" compare "$root/scenes/fig1-symmetry.yaml" --symmetry 2,4 --set 'camera.resolution=[400, 400]' \
    -o "$tmp/ab.png" --quiet >/dev/null
"$bin" compare "$root/scenes/fig1-editing.yaml" --variants edited,smoothed --set 'camera.resolution=[400, 400]' \
    -o "$tmp/cd.png" --quiet >/dev/null
oiiotool "$tmp/ab.png" "$tmp/cd.png" --mosaic 2x1 -o "$root/docs/gallery-compare.png"
ls -l "$root/docs/gallery.png" "$root/docs/gallery-compare.png"
