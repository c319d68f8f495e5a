#!/bin/bash
# Packs a Release build for a GPU machine (see scripts/device/measure.sh): the
# programs, the shared libraries they load that are not part of glibc, the Vulkan
# validation layer and the sample CT, into .device/ (ignored by git) for the device tool
# to carry. The SPIR-V is compiled into the programs, so nothing else is needed.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
out=$root/.device
rm -rf "$out" && mkdir -p "$out/stage/bin" "$out/stage/lib" "$out/stage/layers"
progs=("$build/tools/mpumesh" "$build/tools/mpumesh_bench_mpu" "$build/tools/mpumesh_bench_run"
       "$build/tests/test_host")
cp "${progs[@]}" "$out/stage/bin/"
for p in "${progs[@]}"; do ldd "$p"; done | awk '/=> \//{print $3}' | sort -u |
  grep -v -E '/(libc|libm|libpthread|libdl|librt|libgcc_s|libstdc\+\+)\.so' |
  while read -r lib; do cp -L "$lib" "$out/stage/lib/"; done
cp -L /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$out/stage/layers/"
sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' \
  /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json >"$out/stage/layers/VkLayer_khronos_validation.json"
cp /usr/share/doc/invesalius-examples/examples/Cranium.inv3 "$out/stage/"
tar -C "$out/stage" -cJf "$out/bundle.tar.xz" .
rm -rf "$out/stage"
du -h "$out/bundle.tar.xz"
