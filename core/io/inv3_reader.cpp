// InVesalius 3 projects: main.plist names the matrix file, its numpy dtype and shape
// (z, y, x), and the voxel spacing (x, y, z) in mm. InVesalius stores no origin or
// direction: the volume is placed at the origin with identity direction. Each mask is a
// uint8 array of the matrix's shape plus one plane on every axis (InVesalius's markers of
// edited slices, at index 0), 255 inside.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <map>

#include "common/error.h"
#include "io/plist.h"
#include "io/targz.h"
#include "io/volume_io.h"

namespace mpumesh {

namespace {

// The project's files and main.plist, parsed once.
struct Inv3Project {
  std::string tar;  // the files below point into it
  std::map<std::string, std::string_view> files;
  plist::Value root;
  std::string doc;  // "NAME (main.plist)" for messages

  Inv3Project(const std::string& bytes, const std::string& name) : tar(gunzip(bytes, name, uint64_t(8) << 30)) {
    files = untar(tar, name);
    auto main_it = files.find("main.plist");
    if (main_it == files.end()) throw InputError(name + ": not an InVesalius project (no main.plist)");
    doc = name + " (main.plist)";
    root = plist::parse(std::string(main_it->second), doc);
  }

  std::string_view file(const std::string& fname, const std::string& name) const {
    auto it = files.find(fname);
    if (it == files.end()) throw InputError(name + ": the file '" + fname + "' named by the project is missing");
    return it->second;
  }
};

// The matrix's grid (dims x, y, z from its shape z, y, x; the spacing) with no voxels.
Volume matrix_grid(const Inv3Project& p, const std::string& name) {
  const plist::Value& shape = p.root.at("matrix", p.doc).at("shape", p.doc);
  const plist::Value& spacing = p.root.at("spacing", p.doc);
  if (shape.type != plist::Value::Type::kArray || shape.array.size() != 3)
    throw InputError(p.doc + ": matrix shape must have 3 entries (z, y, x)");
  if (spacing.type != plist::Value::Type::kArray || spacing.array.size() != 3)
    throw InputError(p.doc + ": spacing must have 3 entries");
  Volume v;
  v.source = name;
  for (int a = 0; a < 3; ++a) {
    double n = shape.array[size_t(2 - a)].as_number(p.doc);
    if (!(n >= 1 && n <= 65536) || n != double(int64_t(n)))
      throw InputError(p.doc + ": matrix shape entry " + std::to_string(n) + " is not a positive size");
    v.dims[size_t(a)] = int64_t(n);
    v.spacing[a] = spacing.array[size_t(a)].as_number(p.doc);
  }
  return v;
}

}  // namespace

Volume parse_inv3(const std::string& bytes, const std::string& name) {
  const Inv3Project project(bytes, name);
  const std::string& doc = project.doc;
  const plist::Value& root = project.root;
  const plist::Value& matrix = root.at("matrix", doc);
  const std::string dtype = matrix.at("dtype", doc).as_string(doc);
  const std::string fname = matrix.at("filename", doc).as_string(doc);
  Volume v = matrix_grid(project, name);
  if (auto it = root.dict.find("modality"); it != root.dict.end() && it->second.type == plist::Value::Type::kString)
    v.modality = it->second.text;
  int bytes_per = 0;
  if (dtype == "int16" || dtype == "uint16") bytes_per = 2;
  else if (dtype == "float32") bytes_per = 4;
  else if (dtype == "uint8" || dtype == "int8") bytes_per = 1;
  else throw InputError(doc + ": unsupported matrix dtype '" + dtype + "'");
  const std::string_view raw = project.file(fname, name);
  const uint64_t need = uint64_t(v.voxel_count()) * uint64_t(bytes_per);
  if (raw.size() != need)
    throw InputError(name + ": " + fname + " holds " + std::to_string(raw.size()) + " bytes, the shape needs " +
                     std::to_string(need) + " (truncated or wrong shape)");
  v.voxels.resize(size_t(v.voxel_count()));
  // numpy's little-endian values, one loop per type.
  const auto convert = [&]<typename T>(T) {
    const char* p = raw.data();
    for (size_t i = 0; i < v.voxels.size(); ++i) {
      T x;
      std::memcpy(&x, p + sizeof(T) * i, sizeof(T));
      v.voxels[i] = float(x);
    }
  };
  if (dtype == "int16") convert(int16_t{});
  else if (dtype == "uint16") convert(uint16_t{});
  else if (dtype == "float32") convert(float{});
  else if (dtype == "uint8") convert(uint8_t{});
  else convert(int8_t{});
  validate_volume(v, name);
  return v;
}

Volume parse_inv3_masks(const std::string& bytes, const std::string& name) {
  const Inv3Project project(bytes, name);
  Volume v = matrix_grid(project, name);
  v.voxels.assign(size_t(v.voxel_count()), 0.0f);
  auto masks_it = project.root.dict.find("masks");
  if (masks_it == project.root.dict.end() || masks_it->second.dict.empty())
    throw InputError(name + ": the project holds no masks");
  const int64_t nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  // The keys are the masks' indices; the map orders "10" before "2", so sort by number.
  std::vector<std::pair<int, std::string>> masks;
  for (const auto& [key, entry] : masks_it->second.dict) {
    char* end = nullptr;
    const long index = std::strtol(key.c_str(), &end, 10);
    if (key.empty() || *end != 0 || index < 0 || index > 250)
      throw InputError(project.doc + ": mask key '" + key + "' is not an index from 0 to 250");
    masks.emplace_back(int(index), entry.as_string(project.doc));
  }
  std::sort(masks.begin(), masks.end());
  for (auto it = masks.rbegin(); it != masks.rend(); ++it) {  // the first mask written last: it wins
    const std::string mdoc = name + " (" + it->second + ")";
    const plist::Value mask = plist::parse(std::string(project.file(it->second, name)), mdoc);
    const std::string_view raw = project.file(mask.at("mask_file", mdoc).as_string(mdoc), name);
    const uint64_t need = uint64_t(nx + 1) * uint64_t(ny + 1) * uint64_t(nz + 1);
    if (raw.size() != need)
      throw InputError(mdoc + ": the mask holds " + std::to_string(raw.size()) + " bytes, the matrix's shape with its "
                       "marker planes needs " + std::to_string(need));
    for (int64_t k = 0; k < nz; ++k)
      for (int64_t j = 0; j < ny; ++j)
        for (int64_t i = 0; i < nx; ++i)
          if (uint8_t(raw[size_t((i + 1) + (nx + 1) * ((j + 1) + (ny + 1) * (k + 1)))]) > 127)
            v.voxels[size_t(v.index(i, j, k))] = float(it->first + 1);
  }
  validate_volume(v, name);
  return v;
}

}  // namespace mpumesh
