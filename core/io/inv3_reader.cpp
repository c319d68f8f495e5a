// InVesalius 3 projects: main.plist names the matrix file, its numpy dtype and shape
// (z, y, x), and the voxel spacing (x, y, z) in mm. InVesalius stores no origin or
// direction: the volume is placed at the origin with identity direction.
#include <cstring>

#include "common/error.h"
#include "io/plist.h"
#include "io/targz.h"
#include "io/volume_io.h"

namespace mpumesh {

Volume parse_inv3(const std::string& bytes, const std::string& name) {
  const std::string tar = gunzip(bytes, name, uint64_t(8) << 30);
  auto files = untar(tar, name);
  auto main_it = files.find("main.plist");
  if (main_it == files.end()) throw InputError(name + ": not an InVesalius project (no main.plist)");
  const std::string doc = name + " (main.plist)";
  const plist::Value root = plist::parse(std::string(main_it->second), doc);
  const plist::Value& matrix = root.at("matrix", doc);
  const std::string dtype = matrix.at("dtype", doc).as_string(doc);
  const std::string fname = matrix.at("filename", doc).as_string(doc);
  const plist::Value& shape = matrix.at("shape", doc);
  const plist::Value& spacing = root.at("spacing", doc);
  if (shape.type != plist::Value::Type::kArray || shape.array.size() != 3)
    throw InputError(doc + ": matrix shape must have 3 entries (z, y, x)");
  if (spacing.type != plist::Value::Type::kArray || spacing.array.size() != 3)
    throw InputError(doc + ": spacing must have 3 entries");
  Volume v;
  v.source = name;
  for (int a = 0; a < 3; ++a) {
    double n = shape.array[size_t(2 - a)].as_number(doc);
    if (!(n >= 1 && n <= 65536) || n != double(int64_t(n)))
      throw InputError(doc + ": matrix shape entry " + std::to_string(n) + " is not a positive size");
    v.dims[size_t(a)] = int64_t(n);
    v.spacing[a] = spacing.array[size_t(a)].as_number(doc);
  }
  if (auto it = root.dict.find("modality"); it != root.dict.end() && it->second.type == plist::Value::Type::kString)
    v.modality = it->second.text;
  int bytes_per = 0;
  if (dtype == "int16" || dtype == "uint16") bytes_per = 2;
  else if (dtype == "float32") bytes_per = 4;
  else if (dtype == "uint8" || dtype == "int8") bytes_per = 1;
  else throw InputError(doc + ": unsupported matrix dtype '" + dtype + "'");
  auto data_it = files.find(fname);
  if (data_it == files.end()) throw InputError(name + ": the matrix file '" + fname + "' is missing");
  const std::string_view raw = data_it->second;
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

}  // namespace mpumesh
