// mpumesh segment: the volume to a binary mask (threshold or Chan-Vese per slice).
// mpumesh points: the volume to an oriented point cloud (contours, caps, PCA normals).
#include <fmt/format.h>

#include <iostream>

#include "cli_util.h"
#include "commands.h"
#include "io/atomic_file.h"
#include "io/point_io.h"
#include "io/volume_io.h"
#include "points/slice_points.h"
#include "seg_cli.h"

namespace mpumesh::tools {

void add_segment_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output;
    SegmentCli seg;
    BackendOptions backend;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("segment", "Segment a volume into a binary mask (Chan-Vese per slice, or threshold)");
  cmd->add_option("input", o->input, "volume: DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3")->required();
  cmd->add_option("-o,--output", o->output, "mask: .nii, .nii.gz, .nrrd or .mha (0/1, the input's geometry)")
      ->required();
  add_segment_options(cmd, o->seg);
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      Progress progress(common.quiet || common.json);
      const SegmentedVolume sv = read_and_segment(o->input, o->seg, o->backend, common, progress);
      const auto& [vol, choice, opt, s] = sv;
      progress.begin("write mask");
      write_volume(seg::mask_volume(s, vol), o->output);
      progress.end();
      nlohmann::json j = segment_json(opt, seg::summarize(s));
      j["input"] = o->input;
      j["output"] = o->output;
      j["backend"] = backend_json(choice);
      j["kernel_ms"] = choice.backend->kernel_ms();
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} inside voxels, {} components ({} after thresholding), {} ({})\n", o->output,
                                 j["inside_voxels"].get<int64_t>(), s.components.count, s.threshold_components.count,
                                 seg::method_name(opt.method), choice.backend->device());
    };
  });
}

nlohmann::json points_json(const pts::SlicePoints& p) {
  const auto& st = p.stats;
  const double n = double(std::max<size_t>(p.cloud.size(), 1));
  return {{"points", p.cloud.size()},
          {"contour_points", st.contour_points},
          {"cap_points", st.cap_points},
          {"contours", st.contours},
          {"pca_radius_mm", st.pca_radius_mm},
          {"degenerate_normals", st.degenerate_normals},
          {"degenerate_fraction", double(st.degenerate_normals) / n},
          {"degenerate_resolution",
           "normal set to the orientation reference: the contour's in-plane outward direction (plus +-z where the "
           "adjacent slices show the surface facing up or down), or +-z for a cap point"},
          {"seconds", {{"contours", st.contour_seconds}, {"caps", st.cap_seconds}, {"normals", st.normal_seconds}}}};
}

void add_points_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output;
    SegmentCli seg;
    BackendOptions backend;
    bool no_caps = false, ruled_caps = false;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("points", "Segment a volume and write its oriented boundary points (x y z nx ny nz)");
  cmd->add_option("input", o->input, "volume: DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3")->required();
  cmd->add_option("-o,--output", o->output, "points: .ply (binary) or .xyz (text), millimetres")->required();
  cmd->add_flag("--no-caps", o->no_caps, "leave out the cap points where a structure ends between slices");
  cmd->add_flag("--ruled-caps", o->ruled_caps,
                "cap heights from the contours alone (a ruled surface between two slices' contours), not from the "
                "grey of the two slabs the surface crosses");
  add_segment_options(cmd, o->seg);
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      Progress progress(common.quiet || common.json);
      const SegmentedVolume sv = read_and_segment(o->input, o->seg, o->backend, common, progress);
      const auto& [vol, choice, opt, s] = sv;
      progress.begin("points");
      pts::PointOptions popt;
      popt.caps = !o->no_caps;
      popt.partial_volume_caps = !o->ruled_caps;
      const pts::SlicePoints p = pts::extract_points(s, vol, popt);
      progress.end();
      progress.begin("write points");
      write_point_cloud(p.cloud, o->output);
      progress.end();
      nlohmann::json j;
      j["input"] = o->input;
      j["output"] = o->output;
      j["segmentation"] = segment_json(opt, seg::summarize(s));
      j["points"] = points_json(p);
      j["backend"] = backend_json(choice);
      j["kernel_ms"] = choice.backend->kernel_ms();
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} points ({} on {} contours, {} on caps), {:.2f}% degenerate normals ({})\n",
                                 o->output, p.cloud.size(), p.stats.contour_points, p.stats.contours,
                                 p.stats.cap_points, 100.0 * j["points"]["degenerate_fraction"].get<double>(),
                                 choice.backend->device());
    };
  });
}

}  // namespace mpumesh::tools
