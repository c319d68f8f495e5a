#!/usr/bin/env bash
# Runs the benchmarks on this machine and writes their output, with the date, the commit
# and the machine, to docs/benchmarks.md; renders the README's pictures (docs/skull.png
# from the sample CT, the label-map and complex pictures). Every figure in that file is what the benchmark printed in this run.
# Usage: bash scripts/benchmarks.sh   (after scripts/setup.sh; takes 10-20 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
B=${BUILD_DIR:-build}/tools
ct=data/Cranium.inv3
mkdir -p data
[ -f "$ct" ] || cp /usr/share/doc/invesalius-examples/examples/Cranium.inv3 "$ct"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

commit=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- . ':!docs' || commit="$commit with uncommitted changes"
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
mem=$(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo)
devices=$("$B/mpumesh" devices 2>&1 | sed 's/^/    /')

# One benchmark: its title, what it measures, then its command and output.
section() {
  local title=$1 what=$2
  shift 2
  echo "running: $*" >&2
  local out
  out=$("$@" 2>&1)
  {
    echo
    echo "## $title"
    echo
    echo "$what"
    echo
    echo '```text'
    echo "\$ $*" | sed -E "s|$B/||g; s|[A-Z_]+=[^ ]* ||g; s|^\\$ env |\$ |"
    echo "$out"
    echo '```'
  } >> "$tmp/body.md"
}

: > "$tmp/body.md"
section "The whole job on the sample CT against its peers" \
  "Ours as \`mpumesh run\` runs it, CGAL Mesh_3 with \`manifold()\` at a similar triangle count, sequential and in its parallel mode (TBB, as many threads as ours), the original MPU mesh and marching cubes, all in this run; distances are to and from the marching-cubes surface. The time ratio that counts is against the faster Mesh_3." \
  "$B/mpumesh_bench_run" "$ct" 226 0 3.4 0.72
section "The sample CT at 45,000 particles against CGAL Mesh_3" \
  "The same at the count the speed target names, CGAL Mesh_3 with \`manifold()\` at a similar triangle count, sequential and parallel; ours and the two Mesh_3 runs in turn three times, and the times are the medians." \
  "$B/mpumesh_bench_run" "$ct" 226 45000 3.4 0.72 auto 3
section "Remeshing the sample CT's marching-cubes surface" \
  "The marching-cubes surface written to a PLY file and remeshed by \`mpumesh run MC.ply --particles 45000\` and by CGAL's isotropic remeshing (three iterations) at the same triangle count, in this run; distances are to and from the marching-cubes surface." \
  "$B/mpumesh_bench_remesh" "$ct" 226 45000
section "Volume meshes" \
  "The sample CT's bone at 45,000 particles filled with tetrahedra (\`run --volume\`) against CGAL Mesh_3's volume mesh of the gray image (cell criteria, sliver perturbation and exudation), sequential and parallel, at about the same surface triangle count, in this run." \
  "$B/mpumesh_bench_volume" "$ct" 226 45000
section "Several labels in one volume mesh" \
  "The material phantoms as label maps filled with tetrahedra, a region per label (\`mpumesh run MAP --labels all -o complex.ply --volume complex.vtu\`, the whole run as a process), against CGAL Mesh_3's multi-label volume mesh of the same labelled image (a subdomain per label) at about the same triangle count and the cell size ours used, sequential and parallel, in this run." \
  "$B/mpumesh_bench_volume" --materials cpu
section "Accuracy against analytic truth" \
  "CT-like phantoms (partial volume, noise, slices thicker than the pixels, tilted shapes), meshed as a user does, scored from the mesh files against the closed form." \
  "$B/mpumesh_bench_truth"
"$B/mpumesh" convert "$ct" --masks -o "$tmp/masks.nii.gz" --quiet
section "Label maps against analytic truth" \
  "Label-map phantoms (each voxel the label at its centre, slices 2-3 times the pixel, tilted) meshed by \`mpumesh run MAP --label 1\`, CGAL Mesh_3 on the same label map (its labelled-image domain) at about the same count, and ours on the grey CT-like scan of the same shape. The slice column is the slice-phase modulation of |H|, computed from the written mesh: each vertex's |H|, the mesh's own discrete mean curvature (the cotangent Laplacian over the mixed Voronoi area, the same for every mesh), is binned by the vertex's phase along the slice axis within the slice period, 8 bins, and the figure is (largest bin's mean - smallest) / the mean over all vertices. A surface without terraces shows under 0.1; a surface that follows the voxels 0.4-0.6." \
  "$B/mpumesh_bench_labels" cpu
section "A real label map" \
  "The sample project's masks as a label map (\`convert --masks\`: bone, label 1, and the soft tissue outside it, label 2), every label meshed by \`run --labels all --separate\` (each label's surface a quarter voxel inside it where it meets the other), the bone's voxels alone (the soft tissue taken as background: the shape the CT's bone threshold gives) meshed by \`run --label 1\`, and the count the grey-volume rule gives for the bone (\`run CT --threshold 226\`)." \
  "$B/mpumesh_bench_labels" cpu --real "$tmp/masks.nii.gz" --grey "$ct:226:1" --no-mesh3
section "Several labels: one multi-material complex" \
  "Material phantoms (a ball split by a tilted plane, a ball in a shell, three sectors of a cylinder meeting along its axis, a ball in a cup one slice away; each voxel the label at its centre, slices 2-3 times the pixel, tilted) meshed by \`mpumesh run MAP --labels all -o complex.ply\`, and CGAL Mesh_3 on the same labelled image at about the same count (its facets tagged by their two subdomains), both scored from the written complexes against the closed form: per interface the distance to its true surface and the normal error (also away from the junction curves), the junction edges against the true curves both ways, each label's volume, triangle shape, closedness of every label's boundary, crossing triangle pairs and triangles on no true interface." \
  "$B/mpumesh_bench_materials" cpu
section "A surface mesh of several parts" \
  "The parts phantom (five closed parts: a ball cut by a plane into two parts that share the cut disc, a ball and a spheroid a fifth of an edge from it, a small ball 3 mm away; tilted) written as PLY and remeshed by \`mpumesh run PARTS.ply -o complex.ply\`, and by CGAL's isotropic remeshing (three iterations) at our triangle count, in the same run; both read back as complexes (CGAL's components tagged against the background) and scored from their triangles, against the parts' smooth surfaces and against the input." \
  "$B/mpumesh_bench_parts" cpu
section "Segmentation and points" "The sample CT's segmentation and point stages on every backend." \
  "$B/mpumesh_bench_points" "$ct" 226
section "MPU fit and evaluation" "The fit of the sample CT's points and the evaluation throughput on every backend." \
  "$B/mpumesh_bench_mpu" "$ct" 226
section "Marching cubes" "The voxel-level baseline on every backend." "$B/mpumesh_bench_mc" "$ct" 226
section "The Python module against the program" \
  "The sample CT meshed by \`mpumesh run\` as a process and by \`mpumesh.read_volume\`, \`run\` and \`write_mesh\` in Debian's python3, alternately." \
  env PYTHONPATH="${BUILD_DIR:-build}/python" MPUMESH_BIN="$B/mpumesh" /usr/bin/python3 tools/bench/bench_python.py "$ct" 226 3
section "A folder of scans through the workflow" \
  "workflow/Snakefile on six CT-like ball phantoms, one job per scan, with one core and with two." \
  env MPUMESH_BIN="$B/mpumesh" /usr/bin/python3 tools/bench/bench_workflow.py 6
section "The sample CT at full resolution" \
  "The CT resampled to 512 x 512 x 324 voxels and meshed at the defaults: stage times, peak memory and the estimate \`run\` checked before its long work." \
  env OUT_DIR="$tmp/large" bash scripts/bench_large.sh

# The README's picture: the sample CT's skull, coloured by Gaussian curvature.
"$B/mpumesh" run "$ct" --threshold 226 --largest 1 -o "$tmp/skull.ply" --quiet --no-self-intersections
"$B/mpumesh" render "$tmp/skull.ply" -o docs/skull.png --color curvature --view=-1,1,1 --size 800x600 \
  --title "sample CT, --largest 1" --quiet

# The README's label-map pictures: the masks' bone at every other slice (3 mm), with the
# in-plane voxel as the fit's tolerance (--eps) and with the label-map rule.
/usr/bin/python3 - "$tmp/masks.nii.gz" "$tmp/masks3.nii.gz" <<'PY'
import sys, nibabel as nib, numpy as np
img = nib.load(sys.argv[1])
a = img.affine.copy(); a[:3, 2] *= 2
nib.save(nib.Nifti1Image(np.asarray(img.dataobj)[:, :, ::2], a, img.header), sys.argv[2])
PY
for rule in voxel grid; do
  eps=(); [ "$rule" = voxel ] && eps=(--eps 0.957)
  "$B/mpumesh" run "$tmp/masks3.nii.gz" --label 1 "${eps[@]}" -o "$tmp/bone_$rule.ply" --quiet
done
"$B/mpumesh" render "$tmp/bone_voxel.ply" -o docs/label_before.png --color curvature --view=0.2,0.5,1 \
  --zoom 124,110,120,65 --range=-0.01:0.01 --size 560x420 --title "voxel tolerance" --quiet
"$B/mpumesh" render "$tmp/bone_grid.ply" -o docs/label_after.png --color curvature --view=0.2,0.5,1 \
  --zoom 124,110,120,65 --range=-0.01:0.01 --size 560x420 --title "grid-step tolerance" --quiet
# The complex of three labels meeting along an axis, coloured by label.
"$B/mpumesh_bench_materials" cpu --no-mesh3 sectors > /dev/null
"$B/mpumesh" render "${TMPDIR:-/tmp}/mpumesh_bench_materials/sectors/complex.ply" -o docs/complex_labels.png \
  --color label --size 560x420 --title "three labels meeting along an axis" --quiet

{
  echo "# Benchmarks"
  echo
  echo "Written by \`scripts/benchmarks.sh\` from the benchmarks' own output."
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- commit: $commit"
  echo "- machine: $cpu, $(nproc) cores, $mem"
  echo "- Vulkan devices:"
  echo
  echo "$devices"
  echo
  echo "Timings on one machine drift by 30% and more within an hour: compare the figures of"
  echo "one run with each other, not with another run's."
  cat "$tmp/body.md"
} > docs/benchmarks.md.partial
mv docs/benchmarks.md.partial docs/benchmarks.md
echo "wrote docs/benchmarks.md and docs/skull.png"
