#!/usr/bin/env bash
# The main job on the bundled sample CT: install, build, fetch the InVesalius head CT
# (Debian package invesalius-examples) into data/, convert it to MetaImage, and mesh the
# bone (226 HU) with its JSON and HTML reports and a picture into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BIN=${BUILD_DIR:-build}/tools/mpumesh

mkdir -p data out
src=/usr/share/doc/invesalius-examples/examples/Cranium.inv3
[ -f data/Cranium.inv3 ] || cp "$src" data/Cranium.inv3
[ -f data/cranium.mha ] || "$BIN" convert data/Cranium.inv3 -o data/cranium.mha

"$BIN" devices
"$BIN" run data/Cranium.inv3 --threshold 226 -o out/skull.ply --report out/skull-report.json \
  --html out/skull-report.html
"$BIN" render out/skull.ply -o out/skull.png --color curvature --view=-1,1,1 --quiet
echo "wrote out/skull.ply (with normals and curvature), out/skull-report.json, out/skull-report.html, out/skull.png"
