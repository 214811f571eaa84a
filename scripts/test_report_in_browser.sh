#!/usr/bin/env bash
# CTest `report_in_browser`: the reports of an odometry run (the demo) and of a map run open in
# headless Chromium with no console error, draw their charts and 3D view, and place their ruler
# and clock labels where the distances are (scripts/check_report_in_browser.py).
# Usage: test_report_in_browser.sh PIPESCOPE WORK_DIR
set -euo pipefail
pipescope=$1
work=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work"
mkdir -p "$work"

"$pipescope" demo --out "$work/demo" --frames 120 -q
python3 "$here/check_report_in_browser.py" "$work/demo/run/report.html" \
  --screenshot "$work/odometry_report.png"

"$pipescope" simulate --preset fiberglass-network --out "$work/network" --frames 60 \
  --set layout=straight --set length_m=2 --set speed_m_s=0.075 --set white_card_count=1 -q
printf 'window_interval: 8\nmin_cluster_size: 3\n' > "$work/map.yaml"
"$pipescope" map "$work/network" --out "$work/map" --config "$work/map.yaml" -q
python3 "$here/check_report_in_browser.py" "$work/map/report.html" \
  --screenshot "$work/map_report.png"
