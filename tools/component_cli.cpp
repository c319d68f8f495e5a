#include "component_cli.h"

#include <fmt/format.h>

#include <algorithm>

namespace mpumesh::tools {

void add_component_options(CLI::App* cmd, ComponentOptions& f) {
  cmd->add_option("--largest", f.largest,
                  "keep the N structures of largest enclosed volume (each with its cavities), e.g. 1 for the skull "
                  "without the scanner's head rest")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--min-volume", f.min_volume_mm3, "drop the structures that enclose less than this (mm3)")
      ->check(CLI::NonNegativeNumber);
}

nlohmann::json components_json(const ComponentOptions& f, int64_t kept, const std::vector<DroppedComponent>& dropped) {
  nlohmann::json d = nlohmann::json::array();
  for (const DroppedComponent& c : dropped)
    d.push_back({{"triangles", c.triangles},
                 {"vertices", c.vertices},
                 {"volume_mm3", c.volume_mm3},
                 {"area_mm2", c.area_mm2},
                 {"thin", c.thin},
                 {"centre_mm", {c.centre.x(), c.centre.y(), c.centre.z()}}});
  const auto thin = std::count_if(dropped.begin(), dropped.end(), [](const DroppedComponent& c) { return c.thin; });
  return {{"largest", f.largest},   {"min_volume_mm3", f.min_volume_mm3}, {"min_thickness_mm", f.min_thickness_mm},
          {"kept", kept},           {"dropped", d},                       {"thin_dropped", thin}};
}

std::string components_text(int64_t kept, const std::vector<DroppedComponent>& dropped) {
  std::string s = fmt::format("kept {} structure{}; dropped {}\n", kept, kept == 1 ? "" : "s", dropped.size());
  for (size_t i = 0; i < dropped.size() && i < 10; ++i)
    s += fmt::format("  dropped: {} triangles enclosing {:.1f} mm3 around ({:.1f}, {:.1f}, {:.1f}) mm\n",
                     dropped[i].triangles, dropped[i].volume_mm3, dropped[i].centre.x(), dropped[i].centre.y(),
                     dropped[i].centre.z());
  if (dropped.size() > 10) s += fmt::format("  and {} smaller\n", dropped.size() - 10);
  return s;
}

}  // namespace mpumesh::tools
