// The data arrays of a VTK XML unstructured grid (.vtu) as numbers: ASCII, or inline
// binary as VTK and meshio write it by default: base64 of a header of counts (UInt32 or
// UInt64, the file's header_type) and the raw little-endian values, the values in blocks
// compressed with zlib when the file names vtkZLibDataCompressor. Appended data is not
// read.
#pragma once

#include <string>
#include <vector>

namespace mpumesh {

class VtuArrays {
 public:
  // `text` is the whole file (it must outlive this); `path` names it in errors.
  VtuArrays(const std::string& text, std::string path);
  // Whether an array of this name is present.
  bool has(const std::string& name) const;
  // The values of the array named `name`, or of the first array after the tag `<Points>`
  // when name is empty; throws InputError naming the file when it is absent or malformed.
  std::vector<double> numbers(const std::string& name) const;

 private:
  std::vector<double> decode(size_t tag_at) const;
  const std::string& text_;
  std::string path_;
  bool header64_ = false, zlib_ = false;
};

}  // namespace mpumesh
