# Sourced by the fisheye benchmarks (fisheye_mapping_accuracy.sh, fisheye_colmap.sh): the
# simulated datasets they share, so that both measure the same frames.

# simulate_fisheye PIPESCOPE OUT NAME FRAMES [--set key=value ...]: the fiberglass-network preset
# at 7.5 cm/s (1 cm a frame), simulated into OUT/NAME once and kept.
simulate_fisheye() {
  local pipescope=$1 out=$2 name=$3 frames=$4
  shift 4
  if [ ! -f "$out/$name/dataset.yaml" ]; then
    "$pipescope" simulate --preset fiberglass-network --frames "$frames" --set speed_m_s=0.075 \
      --set speed_variation=0.05 "$@" --out "$out/$name" -q
  fi
}

# simulate_straight PIPESCOPE OUT: OUT/straight, the 850-frame straight pipe (8.4 m of travel).
simulate_straight() {
  simulate_fisheye "$1" "$2" straight 850 --set layout=straight --set length_m=9
}

# link_straight_head OUT: OUT/straight-head, the first 340 frames of OUT/straight (3.39 m),
# linked, not simulated again.
link_straight_head() {
  local out=$1
  local head=$out/straight-head
  mkdir -p "$head/images"
  for f in $(ls "$out/straight/images" | head -340); do
    ln -sf "$out/straight/images/$f" "$head/images/$f"
  done
  cp "$out/straight/dataset.yaml" "$out/straight/camera.yaml" "$out/straight/scene.yaml" \
    "$out/straight/gain_mask.png" "$head/"
  head -341 "$out/straight/groundtruth.tum" >"$head/groundtruth.tum" # a comment line, 340 poses
}
