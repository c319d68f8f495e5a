#!/usr/bin/env bash
# Writes docs/cli.md, the reference of every command and option, from the built program's
# own --help (the test Docs.CliReferenceIsTheProgramsHelp fails when the two differ).
# Usage: bash scripts/cli_doc.sh [path/to/mpumesh]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-build/tools/mpumesh}
help() { "$BIN" "$@" --help | sed -E 's|^Usage: [^ ]*mpumesh|Usage: mpumesh|'; }
subcommands=$("$BIN" --help | awk '/^Subcommands:/ {on = 1; next} on && NF {print $1}')
{
  echo "# Command reference"
  echo
  echo "Every command of \`mpumesh\`, as its \`--help\` prints it. Common to all: \`-q,--quiet\`"
  echo "prints only errors, \`--json\` a machine-readable summary on standard output; on a"
  echo "terminal, long work prints each stage with its time, and the long stages of \`run\` and"
  echo "\`tetmesh\` (particles, triangulation, optimisation, tetrahedra, the loop over labels) a bar"
  echo "with the time left; off a terminal, \`--progress\` prints a line per tenth of each instead."
  echo "Paths are chosen by extension:"
  echo "volumes \`.nii\`, \`.nii.gz\`, \`.nrrd\`, \`.nhdr\`, \`.mha\`, \`.mhd\`, \`.inv3\`, \`.dcm\` or a DICOM"
  echo "directory; meshes \`.ply\`, \`.stl\`, \`.obj\`, \`.off\`; points \`.ply\`, \`.xyz\`; surfaces \`.mpu\`."
  echo "A refusal is one line, \`mpumesh: error: FILE: problem\`, with exit code 1, and leaves no"
  echo "output behind."
  echo
  echo '```text'
  help
  echo '```'
  for s in $subcommands; do
    echo
    echo "## mpumesh $s"
    echo
    echo '```text'
    help "$s"
    echo '```'
  done
} > docs/cli.md.partial
mv docs/cli.md.partial docs/cli.md
echo "wrote docs/cli.md ($(wc -l < docs/cli.md) lines)"
