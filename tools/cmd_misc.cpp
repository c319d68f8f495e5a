// mpumesh devices (the Vulkan devices and the one each backend choice takes) and
// mpumesh convert (volume format conversion, also to a DICOM series).
#include <fmt/format.h>

#include <array>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common/error.h"
#include "common/text.h"
#include "io/atomic_file.h"
#include "io/read_file.h"
#include "io/volume_io.h"
#include "vk/context.h"

namespace mpumesh::tools {

void add_devices_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  auto* cmd = app.add_subcommand("devices", "List the Vulkan devices and the one each --backend would use");
  cmd->add_flag("--json", common.json, "print JSON");
  cmd->callback([&common, &action] {
    action = [&common] {
      const auto devs = vk::list_devices();
      const int hw = vk::default_device_index(devs, true);
      const int any = vk::default_device_index(devs, false);
      if (common.json) {
        nlohmann::json j;
        j["devices"] = nlohmann::json::array();
        for (const auto& d : devs)
          j["devices"].push_back({{"index", d.index},
                                  {"name", d.name},
                                  {"type", d.type},
                                  {"api", fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(d.api_version),
                                                      VK_API_VERSION_MINOR(d.api_version),
                                                      VK_API_VERSION_PATCH(d.api_version))},
                                  {"device_local_mib", d.device_local_bytes >> 20},
                                  {"compute", d.has_compute}});
        j["gpu"] = any;
        j["auto"] = hw >= 0 ? nlohmann::json(hw) : nlohmann::json("cpu");
        std::cout << j.dump(2) << '\n';
        return;
      }
      if (devs.empty()) std::cout << "no Vulkan device found (install mesa-vulkan-drivers for the software device)\n";
      for (const auto& d : devs)
        std::cout << fmt::format("{}: {} [{}], Vulkan {}.{}, {} MiB device-local{}\n", d.index, d.name, d.type,
                                 VK_API_VERSION_MAJOR(d.api_version), VK_API_VERSION_MINOR(d.api_version),
                                 d.device_local_bytes >> 20, d.has_compute ? "" : ", no compute queue");
      std::cout << "--backend gpu  uses " << (any >= 0 ? fmt::format("device {}", any) : std::string("nothing (fails)"))
                << "\n--backend auto uses "
                << (hw >= 0 ? fmt::format("device {}", hw) : std::string("the native CPU path (no hardware GPU)")) << "\n";
    };
  });
}

void add_convert_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output, size;
    bool dicom = false, masks = false;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("convert", "Convert a volume (e.g. an InVesalius .inv3) to NIfTI, NRRD, "
                                            "MetaImage or a DICOM series");
  cmd->add_option("input", o->input, "volume: DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3")->required();
  cmd->add_option("-o,--output", o->output, ".nii, .nii.gz, .nrrd, .mha, or a directory with --dicom")->required();
  cmd->add_flag("--dicom", o->dicom, "write a DICOM series (one file per slice) into the output directory");
  cmd->add_flag("--masks", o->masks,
                "an .inv3 project's masks as one label map: mask i is label i+1, the first mask wins where they "
                "overlap");
  cmd->add_option("--size", o->size,
                  "XxYxZ: resample (trilinear) to this many voxels over the same extent, e.g. 512x512x324");
  cmd->add_flag("--quiet,-q", common.quiet, "print nothing but errors");
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      if (!o->dicom) check_writable(o->output);
      std::array<int64_t, 3> dims{};
      if (!o->size.empty()) {
        int n = 0;
        long long x = 0, y = 0, z = 0;
        if (std::sscanf(o->size.c_str(), "%lldx%lldx%lld%n", &x, &y, &z, &n) != 3 || size_t(n) != o->size.size() ||
            x < 2 || y < 2 || z < 2 || x > 8192 || y > 8192 || z > 8192)
          throw InputError("--size: '" + o->size + "' is not XxYxZ with whole numbers from 2 to 8192");
        dims = {x, y, z};
      }
      if (o->masks && !lower_case(o->input).ends_with(".inv3"))
        throw InputError(o->input + ": --masks reads an InVesalius project (.inv3)");
      if (o->masks && !o->size.empty())
        throw InputError(o->input + ": --masks makes a label map, which --size would blend (trilinear)");
      Volume v = o->masks ? parse_inv3_masks(read_file(o->input), o->input) : read_volume(o->input);
      if (!o->size.empty()) v = resample(v, dims);
      if (o->dicom) write_dicom_series(v, o->output);
      else write_volume(v, o->output);
      if (!common.quiet)
        std::cout << fmt::format("{}: {} x {} x {} voxels, spacing {:.4f} x {:.4f} x {:.4f} mm\n", o->output,
                                 v.dims[0], v.dims[1], v.dims[2], v.spacing.x(), v.spacing.y(), v.spacing.z());
    };
  });
}

}  // namespace mpumesh::tools
