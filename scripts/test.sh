#!/usr/bin/env bash
# Install, build (Release) and run the whole test suite. Tests that need a Vulkan device,
# the sample data or a browser fail (not skip) when they are missing, since this script
# installs all three (lavapipe from mesa-vulkan-drivers, the CT from invesalius-examples,
# chromium).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export MPUMESH_REQUIRE_VULKAN=${MPUMESH_REQUIRE_VULKAN:-1}
export MPUMESH_REQUIRE_DATA=${MPUMESH_REQUIRE_DATA:-1}
export MPUMESH_REQUIRE_BROWSER=${MPUMESH_REQUIRE_BROWSER:-1}
ctest --test-dir "${BUILD_DIR:-build}" -j "$(nproc)" --output-on-failure --timeout 900
