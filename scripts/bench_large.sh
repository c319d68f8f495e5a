#!/usr/bin/env bash
# The full-resolution case: the sample CT resampled (trilinear, same extent) to
# 512 x 512 x 324 voxels of 0.4785 x 0.4785 x 0.5 mm by
#   mpumesh convert Cranium.inv3 -o cranium512.mha --size 512x512x324
# then the whole run on it, with every stage's time, the peak memory (getrusage) and the
# estimate the run checked before its long work, the quality, and any raise of the particle
# count (run samples again when the triangulation shows the default too sparse). Targets:
# under 2 GiB and 45 s on 2 cores, smallest angle 25 degrees or more.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BUILD_DIR:-build}/tools/mpumesh
out=${OUT_DIR:-out/large}
mkdir -p "$out"
src=/usr/share/doc/invesalius-examples/examples/Cranium.inv3
[ -f "$out/cranium512.mha" ] || "$BIN" convert "$src" -o "$out/cranium512.mha" --size 512x512x324
start=$(date +%s.%N)
"$BIN" run "$out/cranium512.mha" --threshold 226 -o "$out/skull512.ply" --report "$out/skull512.json" \
  --no-self-intersections --quiet "$@"
end=$(date +%s.%N)
/usr/bin/python3 - "$out/skull512.json" "$start" "$end" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
wall = float(sys.argv[3]) - float(sys.argv[2])
print("512 x 512 x 324 (0.4785 x 0.4785 x 0.5 mm), bone at 226 HU, on", j["backend"]["device"])
print("%-12s %8s" % ("stage", "s"))
for k, v in sorted(j["stage_seconds"].items(), key=lambda kv: -kv[1]):
    print("%-12s %8.2f" % (k, v))
m = j["memory"]
print("points %d, leaves %d, particles %d, triangles %d" % (j["points"], j["fit"]["leaves"],
      j["particles"]["particles"], j["triangles"]))
print("wall %.1f s (target 45 s); peak memory %.2f GiB (target 2), estimated %.2f GiB, available %.1f GiB"
      % (wall, m["peak_rss_gib"], m["estimate_gib"], m["available_gib"]))
print("malloc huge pages:", "yes" if m["malloc_huge_pages"] else "no")
q = j["quality"]
print("closed %s, oriented %s; smallest angle %.2f deg, %.2f%% of triangles under 30 deg, mean radius ratio %.3f"
      % (q["closed"], q["oriented"], q["min_angle_deg"]["min"], q["pct_min_angle_below"]["30"],
         q["radius_ratio"]["mean"]))
print("repair points %d" % j["triangulation"]["repair_points"])
for r in j["particles"]["count_raises"]:
    print("count raised: %d repair points for %d particles (asked %s) were too many"
          % (r["repair_points"], r["particles"], r["requested_particles"] or "the default"))
for n in j["notes"]:
    print("note:", n)
PY
