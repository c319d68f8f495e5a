#!/usr/bin/env bash
# The main job on the bundled sample CT: install, build, fetch the InVesalius head CT
# (Debian package invesalius-examples) into data/, convert it to MetaImage, and mesh the
# bone (226 HU) with its quality report into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BIN=${BUILD_DIR:-build}/tools/mpumesh

mkdir -p data out
src=/usr/share/doc/invesalius-examples/examples/Cranium.inv3
[ -f data/Cranium.inv3 ] || cp "$src" data/Cranium.inv3
[ -f data/cranium.mha ] || "$BIN" convert data/Cranium.inv3 -o data/cranium.mha

"$BIN" devices
"$BIN" run data/Cranium.inv3 --threshold 226 -o out/skull.ply --report out/skull-report.json
echo "wrote out/skull.ply and out/skull-report.json"
