#include "seg_cli.h"

#include <cmath>

#include "io/volume_io.h"

namespace mpumesh::tools {

void add_segment_options(CLI::App* cmd, SegmentCli& s) {
  cmd->add_option("--method", s.method,
                  "chan-vese (per slice, started from the threshold) or threshold; default chan-vese, or "
                  "threshold when --threshold is given alone")
      ->check(CLI::IsMember({"chan-vese", "threshold"}));
  cmd->add_option_function<std::string>(
         "--threshold",
         [&s](const std::string& v) {
           s.threshold = v;
           s.threshold_given = true;
         },
         "inside range LO or LO:HI (HU for CT; default 226, bone)");
  cmd->add_option("--window", s.window, "Chan-Vese: intensities LO:HI mapped to 0..255 (default 100:1500, bone)");
  cmd->add_option("--lambda1", s.cv.lambda1, "Chan-Vese: weight of the inside fit")->capture_default_str();
  cmd->add_option("--lambda2", s.cv.lambda2, "Chan-Vese: weight of the outside fit")->capture_default_str();
  cmd->add_option("--mu", s.cv.mu, "Chan-Vese: length weight (0.1*255^2)")->capture_default_str();
  cmd->add_option("--nu", s.cv.nu, "Chan-Vese: area weight")->capture_default_str();
  cmd->add_option("--dt", s.cv.dt, "Chan-Vese: time step")->capture_default_str();
  cmd->add_option("--iterations", s.cv.iterations, "Chan-Vese: iterations")->capture_default_str();
  cmd->add_option("--epsilon", s.cv.epsilon, "Chan-Vese: width of the regularised Dirac (pixels)")
      ->capture_default_str();
}

seg::SegmentOptions resolve(const SegmentCli& s) {
  seg::SegmentOptions o;
  if (s.method.empty()) o.method = s.threshold_given ? seg::Method::kThreshold : seg::Method::kChanVese;
  else o.method = s.method == "threshold" ? seg::Method::kThreshold : seg::Method::kChanVese;
  o.threshold = mc::parse_threshold(s.threshold);
  if (!s.window.empty()) o.window = seg::parse_window(s.window);
  o.cv = s.cv;
  if (o.method == seg::Method::kChanVese) seg::validate(o.cv);
  return o;
}

SegmentedVolume read_and_segment(const std::string& input, const SegmentCli& s, const BackendOptions& b,
                                 const CommonOptions& common, Progress& progress) {
  SegmentedVolume r;
  r.options = resolve(s);
  progress.begin("read volume");
  r.volume = read_volume(input);
  progress.end();
  r.backend = open_backend(b, common, progress);
  progress.begin("segment");
  r.segmentation = seg::segment(r.volume, r.options, *r.backend.backend);
  progress.end();
  return r;
}

nlohmann::json segment_json(const seg::SegmentOptions& opt, const seg::SegmentationSummary& s) {
  nlohmann::json j;
  j["method"] = seg::method_name(opt.method);
  j["threshold"] = {{"lo", opt.threshold.lo},
                    {"hi", std::isinf(opt.threshold.hi) ? nlohmann::json() : nlohmann::json(opt.threshold.hi)}};
  j["inside_voxels"] = s.inside_voxels;
  j["components_threshold"] = s.threshold_components;
  j["components"] = s.components;
  j["largest_component_voxels"] = s.largest_component_voxels;
  if (opt.method == seg::Method::kChanVese) {
    j["chan_vese"] = {{"window", {opt.window.lo, opt.window.hi}},
                      {"lambda1", opt.cv.lambda1},
                      {"lambda2", opt.cv.lambda2},
                      {"mu", opt.cv.mu},
                      {"nu", opt.cv.nu},
                      {"dt", opt.cv.dt},
                      {"epsilon", opt.cv.epsilon},
                      {"eta", opt.cv.eta},
                      {"iterations", opt.cv.iterations}};
  }
  return j;
}

}  // namespace mpumesh::tools
