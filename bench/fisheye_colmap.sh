#!/bin/bash
# Peer comparison for issue 7: COLMAP (Debian's `colmap`, CPU only) on the frames of the fisheye
# straight-pipe benchmark (bench/fisheye_mapping_accuracy.sh), beside `pipescope map` on the same
# frames. COLMAP gets one shared OPENCV_FISHEYE camera fitted to camera.yaml up to MAX_ANGLE_DEG
# (default 85: OPENCV_FISHEYE projects through x/z and cannot hold rays at or past 90 degrees;
# features beyond the angle are masked) and kept fixed; SIFT, the sequential matcher, the
# incremental mapper. Its largest model becomes a TUM trajectory (images.txt holds
# cam_from_world; TUM wants world_from_cam) timed like the dataset's frames, evaluated by
# `pipescope evaluate --align sim3` since COLMAP has no metric scale. Results are recorded in
# docs/fisheye_mapping.md.
# Usage: bench/fisheye_colmap.sh BUILD_DIR OUT_DIR [straight|head|tee]
#   head = the first 340 frames, linked as in fisheye_mapping_accuracy.sh; tee = the network's
#   first 300 frames (0.9 m of the start arm, T1 and 1.7 m of the T1-T2 side; issue 23).
#   BUILD_DIR holds bench/fisheye_colmap_camera and, unless PIPESCOPE=FILE names another build's
#   program, pipescope. Finished stages are kept and not run again (delete OUT_DIR/<name>-colmap
#   or <name>-pipescope to redo them). Environment: MAX_ANGLE_DEG (85), OVERLAP (sequential
#   matcher, 10), MAX_FEATURES (SIFT features an image, 4096), PEAK_THRESHOLD (SIFT's, COLMAP's
#   0.0067; lower finds features on the weakly textured stretches), THREADS (1, for each COLMAP
#   stage), STAGE_TIMEOUT (seconds a stage may take, 3600), TAG (a suffix for COLMAP's directory,
#   to keep runs with other options apart).
set -euo pipefail
BUILD_DIR=${1:?usage: bench/fisheye_colmap.sh BUILD_DIR OUT_DIR [straight|head|tee]}
OUT=${2:?usage: bench/fisheye_colmap.sh BUILD_DIR OUT_DIR [straight|head|tee]}
WHICH=${3:-head}
P=${PIPESCOPE:-$BUILD_DIR/pipescope}
FIT=$BUILD_DIR/bench/fisheye_colmap_camera
MAX_ANGLE_DEG=${MAX_ANGLE_DEG:-85}
OVERLAP=${OVERLAP:-10}
MAX_FEATURES=${MAX_FEATURES:-4096}
THREADS=${THREADS:-1}
PEAK_THRESHOLD=${PEAK_THRESHOLD:-0.0066666666666666671}
STAGE_TIMEOUT=${STAGE_TIMEOUT:-3600}
case "$WHICH" in straight | head | tee) ;; *)
  echo "unknown subset '$WHICH' (expected straight, head or tee)" >&2
  exit 2
  ;;
esac
for f in "$P" "$FIT"; do
  [ -x "$f" ] || { echo "missing $f: build it first (make build)" >&2; exit 2; }
done

# COLMAP from Debian, installed when missing as scripts/install_deps.sh does.
if ! dpkg-query -W -f='${Status}' colmap 2>/dev/null | grep -q "install ok installed"; then
  echo "Installing missing Debian package: colmap"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends colmap
fi

mkdir -p "$OUT"
source "$(dirname "$0")/fisheye_datasets.sh"
if [ "$WHICH" = tee ]; then
  simulate_fisheye "$P" "$OUT" tee 300
  D=$OUT/tee
else
  simulate_straight "$P" "$OUT"
  D=$OUT/straight
fi
if [ "$WHICH" = head ]; then
  D=$OUT/straight-head
  [ -f "$D/groundtruth.tum" ] || link_straight_head "$OUT"
fi
C=$D-colmap${TAG:+-$TAG}
R=$D-pipescope
mkdir -p "$C"

# run_stage NAME COMMAND...: runs once, logs to $C/NAME.log, and writes to $C/NAME.time its
# wall-clock and CPU (user + system) seconds: the machine is shared, so the CPU time is the
# figure that other loads do not inflate.
run_stage() {
  local name=$1
  shift
  if [ -f "$C/$name.time" ]; then return 0; fi
  echo "$(date -u +%H:%M:%S) $name ($(uptime | sed 's/.*load/load/'))" >&2
  if ! /usr/bin/time -f "%e %U %S" -o "$C/$name.cpu" timeout "$STAGE_TIMEOUT" "$@" \
    >"$C/$name.log" 2>&1; then
    echo "$name failed or timed out after $STAGE_TIMEOUT s: see $C/$name.log" >&2
    exit 1
  fi
  awk '{print $1, $2 + $3}' "$C/$name.cpu" >"$C/$name.time"
}

# The camera: OPENCV_FISHEYE parameters and a mask (COLMAP wants one a image, named NAME.png).
if [ ! -f "$C/camera_fit.txt" ]; then
  "$FIT" "$D/camera.yaml" "$MAX_ANGLE_DEG" "$C/mask.png" >"$C/camera_fit.txt"
  mkdir -p "$C/masks"
  for f in $(ls "$D/images"); do ln -sf ../mask.png "$C/masks/$f.png"; done
fi
PARAMS=$(awk '$1 == "opencv_fisheye_params" {print $2}' "$C/camera_fit.txt")

run_stage feature_extractor colmap feature_extractor --database_path "$C/database.db" \
  --image_path "$D/images" --ImageReader.mask_path "$C/masks" \
  --ImageReader.camera_model OPENCV_FISHEYE --ImageReader.single_camera 1 \
  --ImageReader.camera_params "$PARAMS" --SiftExtraction.use_gpu 0 \
  --SiftExtraction.num_threads "$THREADS" --SiftExtraction.max_num_features "$MAX_FEATURES" \
  --SiftExtraction.peak_threshold "$PEAK_THRESHOLD"
run_stage sequential_matcher colmap sequential_matcher --database_path "$C/database.db" \
  --SiftMatching.use_gpu 0 --SiftMatching.num_threads "$THREADS" \
  --SequentialMatching.overlap "$OVERLAP" --SequentialMatching.loop_detection 0
mkdir -p "$C/sparse"
# The intrinsics are the calibration's: COLMAP must not refine them.
run_stage mapper colmap mapper --database_path "$C/database.db" --image_path "$D/images" \
  --output_path "$C/sparse" --Mapper.num_threads "$THREADS" \
  --Mapper.ba_refine_focal_length 0 --Mapper.ba_refine_principal_point 0 \
  --Mapper.ba_refine_extra_params 0
for model in "$C"/sparse/*/; do
  [ -f "$model/images.txt" ] || colmap model_converter --input_path "$model" \
    --output_path "$model" --output_type TXT >/dev/null
done

# The largest model as a TUM trajectory: image i of the sorted folder has the dataset's i-th
# timestamp (docs/formats.md: the manifest's timestamps file, or index / fps).
python3 - "$D" "$C" <<'PY'
import glob, os, sys
dataset, out = sys.argv[1:]
names = sorted(os.listdir(os.path.join(dataset, "images")))
manifest = dict(l.split(":", 1) for l in open(os.path.join(dataset, "dataset.yaml"))
                if ":" in l and not l.startswith((" ", "#")))
manifest = {k.strip(): v.split("#")[0].strip() for k, v in manifest.items()}
if manifest.get("timestamps"):
    times = [float(l) for l in open(os.path.join(dataset, manifest["timestamps"]))
             if l.strip() and not l.startswith("#")]
else:
    times = [i / float(manifest["fps"]) for i in range(len(names))]
index = {name: i for i, name in enumerate(names)}

def world_from_cam(qw, qx, qy, qz, tx, ty, tz):
    # images.txt holds cam_from_world (q, t); the centre is -R^T t, the rotation q's conjugate.
    r = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
         [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
         [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
    t = (tx, ty, tz)
    centre = [-sum(r[j][i] * t[j] for j in range(3)) for i in range(3)]
    return centre, (-qx, -qy, -qz, qw)

models = []
for images_txt in glob.glob(os.path.join(out, "sparse", "*", "images.txt")):
    poses = []
    lines = [l for l in open(images_txt) if not l.startswith("#")]
    for line in lines[0::2]:  # Every other line lists the image's 2D points.
        f = line.split()
        if len(f) < 10:
            continue
        centre, q = world_from_cam(*map(float, f[1:8]))
        poses.append((times[index[f[9]]], centre, q))
    models.append(sorted(poses))
models.sort(key=len, reverse=True)
# colmap.tum is the largest model; colmap_model_K.tum the K-th largest (each has its own scale).
for k, poses in enumerate(models):
    for name in ["colmap.tum"] * (k == 0) + [f"colmap_model_{k}.tum"]:
        with open(os.path.join(out, name), "w") as tum:
            tum.write(f"# COLMAP's model {k} by size, world_from_cam: timestamp tx ty tz qx qy qz qw\n")
            for t, c, q in poses:
                tum.write(f"{t:.9f} {c[0]:.9g} {c[1]:.9g} {c[2]:.9g} "
                          f"{q[0]:.9g} {q[1]:.9g} {q[2]:.9g} {q[3]:.9g}\n")
with open(os.path.join(out, "models.txt"), "w") as f:
    f.write(f"frames {len(names)}\nmodels {len(models)}\nsizes {' '.join(str(len(m)) for m in models)}\n")
PY

# pipescope's own run on the same frames, and both trajectories after Sim(3).
if [ ! -f "$R/run.json" ]; then
  echo "$(date -u +%H:%M:%S) pipescope map ($(uptime | sed 's/.*load/load/'))" >&2
  /usr/bin/time -f "%e %U %S" -o "$R.cpu" timeout "$STAGE_TIMEOUT" "$P" map "$D" --out "$R" -q \
    >/dev/null
fi
evaluate_sim3() { # EST.tum JSON: skipped for fewer than 2 poses, which evaluate refuses
  if [ -s "$1" ] && [ "$(grep -vc '^#' "$1")" -ge 2 ]; then
    "$P" evaluate --gt "$D/groundtruth.tum" --est "$1" --align sim3 --json "$2" -q >/dev/null
  fi
}
for est in "$C"/colmap_model_*.tum; do
  [ -f "$est" ] && evaluate_sim3 "$est" "${est%.tum}_sim3.json"
done
evaluate_sim3 "$C/colmap.tum" "$C/metrics_sim3.json"
evaluate_sim3 "$R/trajectory.tum" "$R/metrics_sim3.json"
# pipescope on exactly the frames of COLMAP's largest model, so the two ATEs cover the same path.
if [ -f "$C/colmap.tum" ]; then
  awk 'NR == FNR { if ($1 !~ /^#/) keep[sprintf("%.6f", $1)] = 1; next }
       /^#/ || (sprintf("%.6f", $1) in keep)' "$C/colmap.tum" "$R/trajectory.tum" \
    >"$C/pipescope_same_frames.tum"
  evaluate_sim3 "$C/pipescope_same_frames.tum" "$C/pipescope_same_frames_sim3.json"
fi

python3 - "$C" "$R" <<'PY'
import json, os, sys
colmap, run = sys.argv[1:]
def scaled_distance_error(m):
    # COLMAP's distances are in its own unit: compare them after the Sim(3) scale.
    return 100 * abs(m["scale"] * m["distance_est_m"] - m["distance_gt_m"]) / m["distance_gt_m"]
fit = dict(l.split() for l in open(os.path.join(colmap, "camera_fit.txt")))
models = dict(l.split(None, 1) for l in open(os.path.join(colmap, "models.txt")))
stages = ["feature_extractor", "sequential_matcher", "mapper"]
# NAME.time: wall-clock seconds, then CPU seconds.
times = {s: [float(x) for x in open(os.path.join(colmap, s + ".time")).read().split()]
         for s in stages}
wall = sum(t[0] for t in times.values())
cpu = sum(t[1] for t in times.values())
frames = int(models["frames"])
sizes = models["sizes"].split()
print(f"{colmap}: OPENCV_FISHEYE fitted up to {fit['fit_max_angle_deg']} deg, residual "
      f"rms {fit['fit_rms_px']} px, max {fit['fit_max_px']} px; mask keeps "
      f"{100 * float(fit['mask_fraction']):.1f} % of the image")
print(f"  registered {sizes[0] if sizes else 0} / {frames} frames in the largest of "
      f"{models['models'].strip()} models (sizes {' '.join(sizes) or '-'})")
path = os.path.join(colmap, "metrics_sim3.json")
if os.path.exists(path):
    m = json.load(open(path))
    print(f"  after Sim(3): ate_rmse_m {m['ate_rmse_m']:.4f}, ate_max_m {m['ate_max_m']:.4f}, "
          f"scale {m['scale']:.5g}, distance gt {m['distance_gt_m']:.3f} m, error after scale "
          f"{scaled_distance_error(m):.2f} %")  # rpe_1m_pct would be in COLMAP's unit
k = 0
while os.path.exists(os.path.join(colmap, f"colmap_model_{k}_sim3.json")):
    m = json.load(open(os.path.join(colmap, f"colmap_model_{k}_sim3.json")))
    print(f"  model {k}: {m['frames_est']} frames, ate_rmse_m {m['ate_rmse_m']:.4f}, "
          f"distance gt {m['distance_gt_m']:.3f} m, error after scale {scaled_distance_error(m):.2f} %")
    k += 1
path = os.path.join(colmap, "pipescope_same_frames_sim3.json")
if os.path.exists(path):
    m = json.load(open(path))
    print(f"  pipescope on the largest model's frames ({m['frames_matched']} matched), after "
          f"Sim(3): ate_rmse_m {m['ate_rmse_m']:.4f}, error after scale {scaled_distance_error(m):.2f} %")
print("  wall clock / CPU: " + ", ".join(f"{s} {t[0]:.0f} / {t[1]:.0f} s" for s, t in times.items())
      + f", total {wall:.0f} / {cpu:.0f} s ({frames / wall:.3f} frames/s wall, "
      f"{frames / cpu:.3f} frames/CPU-s)")
r = json.load(open(os.path.join(run, "run.json")))
se3 = json.load(open(os.path.join(run, "metrics.json")))
sim3 = json.load(open(os.path.join(run, "metrics_sim3.json")))
print(f"{run}: localised {r['counts']['frames_localised']} / {r['counts']['frames']} frames")
print(f"  se3: ate_rmse_m {se3['ate_rmse_m']:.4f}, distance error {se3['distance_error_pct']:.2f} %")
print(f"  after Sim(3): ate_rmse_m {sim3['ate_rmse_m']:.4f}, scale {sim3['scale']:.5g}, "
      f"distance error after scale {scaled_distance_error(sim3):.2f} %")
t = r["timings_s"]
print("  wall clock: " + ", ".join(f"{k} {v:.0f} s" for k, v in t.items() if k != "total") +
      f", total {t['total']:.0f} s ({r['fps_end_to_end']:.3f} frames/s)")
if os.path.exists(run + ".cpu"):  # Absent when the run was made by hand.
    wall, user, system = map(float, open(run + ".cpu").read().split())
    print(f"  CPU {user + system:.0f} s ({r['counts']['frames'] / (user + system):.3f} frames/CPU-s)")
PY
