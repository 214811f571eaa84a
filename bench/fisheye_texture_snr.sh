#!/bin/bash
# How much of the wall's texture a frame of the fisheye target condition still carries
# (docs/conditions.md, "Fisheye straight pipe"): the fisheye1 set-up of bench/conditions.sh,
# seed 1, its first frame rendered four ways that differ in one thing each:
#   clean    texture contrast 0.4, highlights (specular 0.6, exponent 80), no noise at all
#   plain    the same with texture contrast 0 (shading and highlights only)
#   preset   the same with the preset's texture contrast 1
#   target   contrast 0.4 as the condition renders it: noise sigma 3 and the sensor's shot noise
#   busy     the preset's contrast 1 with the preset's noise (sigma 1 and shot noise)
# The texture is clean - plain (and preset - plain), the noise target - clean. Both are
# band-passed (Gaussian sigma s minus sigma 4 s, the scale a template of about 4 s pixels
# sees) and their standard deviations printed, in grey levels, over the wall by its brightness
# (the plain frame blurred by 10 px), with the ratio of texture to noise.
# Needs python3 with numpy and OpenCV (Debian: python3-numpy python3-opencv).
# Usage: bench/fisheye_texture_snr.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_fisheye_texture_snr}
P=$BUILD_DIR/pipescope
mkdir -p "$OUT"
SETUP="--preset fiberglass-network --frames 1 --seed 1 --set layout=straight --set length_m=2.7 \
--set end_margin_m=0.3 --set speed_m_s=0.075 --set speed_variation=0.05 --set wander_wavelength_m=2 \
--set specular_strength=0.6 --set specular_exponent=80"
NO_NOISE="--set noise_sigma=0 --set electrons_per_grey_level=0"
render() {  # NAME ARGS...
  local name=$1
  shift
  [ -f "$OUT/$name/images/000000.png" ] || "$P" simulate $SETUP --out "$OUT/$name" -q "$@"
}
render clean --set texture_contrast=0.4 $NO_NOISE
render plain --set texture_contrast=0 $NO_NOISE
render preset --set texture_contrast=1 $NO_NOISE
render target --set texture_contrast=0.4 --set noise_sigma=3
render busy --set texture_contrast=1
python3 - "$OUT" <<'PY'
import sys
import cv2
import numpy as np

out = sys.argv[1]
frame = {name: cv2.imread(f"{out}/{name}/images/000000.png", cv2.IMREAD_GRAYSCALE)
         .astype(np.float32) for name in ("clean", "plain", "preset", "target", "busy")}
texture = frame["clean"] - frame["plain"]
texture_preset = frame["preset"] - frame["plain"]
noise = frame["target"] - frame["clean"]
brightness = cv2.GaussianBlur(frame["plain"], (0, 0), 10)
print("band sigma  wall brightness  pixels   texture 0.4  texture 1  noise   texture 0.4 / noise"
      "  preset's noise")
busy_noise = frame["busy"] - frame["preset"]
for sigma in (0.0, 1.5, 3.0, 6.0):
    def band(image):
        if sigma == 0.0:
            return image
        return cv2.GaussianBlur(image, (0, 0), sigma) - cv2.GaussianBlur(image, (0, 0), 4 * sigma)
    t, t1, n, n1 = band(texture), band(texture_preset), band(noise), band(busy_noise)
    for low, high in ((40, 256), (10, 40), (3, 10)):
        wall = (brightness >= low) & (brightness < high)
        scale = f"{sigma:8.1f} px" if sigma else "     raw   "
        print(f"{scale}  [{low:3d}, {high:3d})  {wall.sum():9d}  {t[wall].std():9.2f}"
              f"  {t1[wall].std():9.2f}  {n[wall].std():6.2f}  {t[wall].std() / n[wall].std():8.2f}"
              f"  {n1[wall].std():6.2f}")

PY
