#!/usr/bin/env bash
# Writes the binary seed files of the fuzz corpora (kept out of git as a script):
#   tests/fuzz/make_seeds.sh OUT   ->  OUT/mesh_ply/*.ply, OUT/mesh_stl/*.stl, OUT/field/*.bin
# Only bash's printf: no other tool needed on a fresh machine.
set -euo pipefail
out=${1:?usage: make_seeds.sh OUTPUT_FOLDER}
mkdir -p "$out/mesh_ply" "$out/mesh_stl" "$out/field"

# 32-bit floats and ints as printf escapes, little (le) and big (be) endian.
declare -A f32le=([0]='\x00\x00\x00\x00' [1]='\x00\x00\x80\x3f' [-1]='\x00\x00\x80\xbf' [h]='\x00\x00\x00\x3f'
                  [nan]='\x00\x00\xc0\x7f')
declare -A f32be=([0]='\x00\x00\x00\x00' [1]='\x3f\x80\x00\x00' [-1]='\xbf\x80\x00\x00' [h]='\x3f\x00\x00\x00'
                  [nan]='\x7f\xc0\x00\x00')
i32le() { printf '\\x%02x\\x%02x\\x%02x\\x%02x' $(($1 & 255)) $(($1 >> 8 & 255)) $(($1 >> 16 & 255)) $(($1 >> 24 & 255)); }
i32be() { printf '\\x%02x\\x%02x\\x%02x\\x%02x' $(($1 >> 24 & 255)) $(($1 >> 16 & 255)) $(($1 >> 8 & 255)) $(($1 & 255)); }

tetraV=("0 0 0" "1 0 0" "0 1 0" "0 0 1")
tetraF=("0 2 1" "0 1 3" "0 3 2" "1 2 3")

# $1 endianness (le|be), $2 vertex coordinate override for vertex 3 (optional, e.g. "nan 0 1")
ply_binary() {
  local e=$1 nanv=${2:-} fmt=binary_little_endian
  [ "$e" = be ] && fmt=binary_big_endian
  printf 'ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n' "$fmt"
  printf 'element face 4\nproperty list uchar int vertex_indices\nend_header\n'
  local k=0
  for v in "${tetraV[@]}"; do
    [ $k -eq 3 ] && [ -n "$nanv" ] && v=$nanv
    for c in $v; do
      if [ "$e" = le ]; then printf "${f32le[$c]}"; else printf "${f32be[$c]}"; fi
    done
    k=$((k + 1))
  done
  for f in "${tetraF[@]}"; do
    printf '\x03'
    for i in $f; do if [ "$e" = le ]; then printf "$(i32le "$i")"; else printf "$(i32be "$i")"; fi; done
  done
}
ply_binary le > "$out/mesh_ply/tetrahedron_le.ply"
ply_binary be > "$out/mesh_ply/tetrahedron_be.ply"
ply_binary le "nan 0 1" > "$out/mesh_ply/nan_vertex_le.ply"
head -c 200 "$out/mesh_ply/tetrahedron_le.ply" > "$out/mesh_ply/truncated_le.ply"

# Binary triangle strips (int count, int indices, -1 restarts), both byte orders.
ply_strips() {
  local e=$1 fmt=binary_little_endian
  [ "$e" = be ] && fmt=binary_big_endian
  printf 'ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n' "$fmt"
  printf 'element tristrips 1\nproperty list int int vertex_indices\nend_header\n'
  for v in "${tetraV[@]}"; do
    for c in $v; do if [ "$e" = le ]; then printf "${f32le[$c]}"; else printf "${f32be[$c]}"; fi; done
  done
  for i in 12 0 2 1 3 -1 0 1 3 -1 0 3 2; do   # length 12, then three strips: the tetrahedron
    if [ "$e" = le ]; then printf "$(i32le "$i")"; else printf "$(i32be "$i")"; fi
  done
}
ply_strips le > "$out/mesh_ply/tristrips_le.ply"
ply_strips be > "$out/mesh_ply/tristrips_be.ply"

# Binary STL: 80-byte header, uint32 count, per triangle normal + 3 vertices + uint16.
stl_tri() { # three "x y z" corners
  printf "${f32le[0]}${f32le[0]}${f32le[0]}"
  for v in "$1" "$2" "$3"; do for c in $v; do printf "${f32le[$c]}"; done; done
  printf '\x00\x00'
}
stl_binary() { # $1 header start, $2 count written in the header
  printf '%-80s' "$1"
  printf "$(i32le "$2")"
  stl_tri "0 0 0" "0 1 0" "1 0 0"
  stl_tri "0 0 0" "1 0 0" "0 0 1"
  stl_tri "0 0 0" "0 0 1" "0 1 0"
  stl_tri "1 0 0" "0 1 0" "0 0 1"
}
stl_binary "binary tetrahedron" 4 > "$out/mesh_stl/tetrahedron_binary.stl"
stl_binary "solid but binary" 4 > "$out/mesh_stl/solid_header_binary.stl"
stl_binary "count larger than data" 1000000 > "$out/mesh_stl/lying_count.stl"
{ printf '%-80s' "degenerate"; printf "$(i32le 2)"; stl_tri "0 0 0" "0 0 0" "1 0 0"; stl_tri "0 0 0" "h 0 0" "1 0 0"; } \
  > "$out/mesh_stl/degenerate_binary.stl"
{ printf '%-80s' "nan"; printf "$(i32le 1)"; stl_tri "nan 0 0" "0 1 0" "1 0 0"; } > "$out/mesh_stl/nan_binary.stl"

# fuzz_field reads its choices from the end of the input (FuzzedDataProvider); any bytes
# are valid. A few patterns that pick different base meshes, defects and specs.
printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00' > "$out/field/zeros.bin"
printf '\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff' > "$out/field/ones.bin"
for k in 1 2 3 4 5 6 7 8; do
  s=""
  for j in $(seq 1 48); do s+=$(printf '\\x%02x' $(((k * 37 + j * j * 11 + j * k) & 255))); done
  printf "$s" > "$out/field/pattern$k.bin"
done
echo "make_seeds: wrote binary seeds into $out"
