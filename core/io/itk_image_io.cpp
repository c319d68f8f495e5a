// ITK is confined to this file (compile time, and ITK bundles its own Eigen, which must
// not meet the system Eigen in one translation unit: hence PlainVolume). Each format's
// ImageIO is chosen explicitly by extension so that a wrong file gives a message naming
// the format that was expected.
#include "io/itk_image_io.h"

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageSeriesReader.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>
#include <gdcmTrace.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <type_traits>

#include "common/error.h"
#include "common/text.h"
#include "io/atomic_file.h"
#include "io/dicom_kind.h"
#include "io/dicom_pixel_check.h"
#include "io/read_file.h"
#include "io/library_messages.h"
#include "io/volume_integrity.h"

namespace mpumesh {
namespace {

using FloatImage = itk::Image<float, 3>;
namespace fs = std::filesystem;


// ITK's and GDCM's own warnings go to stderr in their words; every problem they find
// reaches the user as one InputError naming the file instead.
void quiet_libraries() {
  static const bool once = [] {
    itk::Object::GlobalWarningDisplayOff();
    gdcm::Trace::SetWarning(false);
    gdcm::Trace::SetError(false);
    gdcm::Trace::SetDebug(false);
    return true;
  }();
  (void)once;
}

itk::ImageIOBase::Pointer io_for(const std::string& path) {
  const std::string p = lower_case(path);
  if (p.ends_with(".nii") || p.ends_with(".nii.gz")) return itk::NiftiImageIO::New().GetPointer();
  if (p.ends_with(".nrrd") || p.ends_with(".nhdr")) return itk::NrrdImageIO::New().GetPointer();
  if (p.ends_with(".mha") || p.ends_with(".mhd")) return itk::MetaImageIO::New().GetPointer();
  if (p.ends_with(".dcm")) return itk::GDCMImageIO::New().GetPointer();
  return nullptr;
}

// The image's geometry and voxels (float, or int16 left in the image's buffer: voxels16).
template <class Image>
PlainVolume from_itk(const Image* img, const std::string&) {
  PlainVolume v;
  const auto size = img->GetLargestPossibleRegion().GetSize();
  for (int a = 0; a < 3; ++a) {
    v.dims[size_t(a)] = int64_t(size[a]);
    v.spacing[size_t(a)] = img->GetSpacing()[a];
    v.origin[size_t(a)] = img->GetOrigin()[a];
    for (int b = 0; b < 3; ++b) v.direction[size_t(3 * a + b)] = img->GetDirection()(a, b);
  }
  const auto* buf = img->GetBufferPointer();
  if constexpr (std::is_same_v<typename Image::PixelType, int16_t>) {
    v.voxels16 = {buf, size_t(size[0] * size[1] * size[2])};
    v.voxels16_owner = std::make_shared<typename Image::ConstPointer>(img);
  } else
    v.voxels.assign(buf, buf + size[0] * size[1] * size[2]);
  return v;
}

// Whether the file's voxels are single 8- or 16-bit integers in a format that applies no
// rescale on reading (MetaImage, NRRD), so that they are read as int16 exactly.
bool stored_as_int16(itk::ImageIOBase* io) {
  if (!dynamic_cast<itk::MetaImageIO*>(io) && !dynamic_cast<itk::NrrdImageIO*>(io)) return false;
  using C = itk::IOComponentEnum;
  const C c = io->GetComponentType();
  return io->GetNumberOfComponents() == 1 && (c == C::SHORT || c == C::CHAR || c == C::UCHAR);
}

template <class Image>
PlainVolume read_as(itk::ImageIOBase* io, const std::string& path) {
  auto reader = itk::ImageFileReader<Image>::New();
  reader->SetImageIO(io);
  reader->SetFileName(path);
  reader->Update();
  return from_itk(reader->GetOutput(), path);
}

FloatImage::Pointer to_itk(const PlainVolume& v) {
  auto img = FloatImage::New();
  FloatImage::RegionType region;
  FloatImage::SizeType size;
  FloatImage::SpacingType spacing;
  FloatImage::PointType origin;
  FloatImage::DirectionType dir;
  for (int a = 0; a < 3; ++a) {
    size[a] = itk::SizeValueType(v.dims[size_t(a)]);
    spacing[a] = v.spacing[size_t(a)];
    origin[a] = v.origin[size_t(a)];
    for (int b = 0; b < 3; ++b) dir(a, b) = v.direction[size_t(3 * a + b)];
  }
  region.SetSize(size);
  img->SetRegions(region);
  img->SetSpacing(spacing);
  img->SetOrigin(origin);
  img->SetDirection(dir);
  img->Allocate();
  std::copy(v.voxels.begin(), v.voxels.end(), img->GetBufferPointer());
  return img;
}

std::string dicom_tag(const itk::MetaDataDictionary& d, const std::string& tag) {
  std::string value;
  itk::ExposeMetaData<std::string>(d, tag, value);
  return value;
}

std::vector<double> parse_numbers(const std::string& s) {
  std::vector<double> out;
  std::string t = s;
  std::replace(t.begin(), t.end(), '\\', ' ');
  std::istringstream is(t);
  double x;
  while (is >> x) out.push_back(x);
  return out;
}

PlainVolume read_series_impl(const std::string& dir) {
  quiet_libraries();
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(true);
  names->SetDirectory(dir);
  const auto& uids = names->GetSeriesUIDs();
  if (uids.empty()) throw InputError(dir + ": no DICOM series found in this directory");
  if (uids.size() > 1)
    throw InputError(dir + ": holds " + std::to_string(uids.size()) +
                     " DICOM series (or slices of different sizes or orientations); put one series per directory");
  const auto files = names->GetFileNames(uids.front());
  if (files.size() < 2) throw InputError(dir + ": the DICOM series has a single slice; a volume needs several");
  for (const auto& f : files) check_dicom_pixel_data_file(f);
  using Reader = itk::ImageSeriesReader<FloatImage>;
  auto reader = Reader::New();
  auto gdcm = itk::GDCMImageIO::New();
  reader->SetImageIO(gdcm);
  reader->SetFileNames(files);
  reader->Update();
  // Slice positions along the normal: GDCM sorted by them; check they are regular.
  const auto* dicts = reader->GetMetaDataDictionaryArray();
  std::vector<double> pos;
  std::vector<double> first_ipp, last_ipp;
  double normal[3] = {0, 0, 1};
  for (size_t i = 0; i < dicts->size(); ++i) {
    auto ipp = parse_numbers(dicom_tag(*(*dicts)[i], "0020|0032"));
    auto iop = parse_numbers(dicom_tag(*(*dicts)[i], "0020|0037"));
    if (ipp.size() != 3) throw InputError(files[i] + ": no ImagePositionPatient (0020,0032)");
    if (i == 0) first_ipp = ipp;
    last_ipp = ipp;
    if (i == 0 && iop.size() == 6) {
      normal[0] = iop[1] * iop[5] - iop[2] * iop[4];
      normal[1] = iop[2] * iop[3] - iop[0] * iop[5];
      normal[2] = iop[0] * iop[4] - iop[1] * iop[3];
      const double len = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
      if (len > 0)
        for (double& c : normal) c /= len;
    }
    pos.push_back(normal[0] * ipp[0] + normal[1] * ipp[1] + normal[2] * ipp[2]);
  }
  // Gantry tilt: the slices are stacked at an angle to their normal (a sheared grid).
  {
    double d[3], len = 0, along = 0;
    for (int a = 0; a < 3; ++a) d[a] = last_ipp[size_t(a)] - first_ipp[size_t(a)], len += d[a] * d[a];
    for (int a = 0; a < 3; ++a) along += d[a] * normal[a];
    len = std::sqrt(len);
    const double deg = len > 0 ? std::acos(std::min(1.0, std::abs(along) / len)) * 180 / 3.14159265358979 : 0;
    if (deg > 0.5)
      throw InputError(dir + ": gantry tilt of " + std::to_string(deg).substr(0, 5) +
                       " degrees (the slices are not stacked along their normal); resample the series to an "
                       "orthogonal grid first");
  }
  for (size_t i = 1; i + 1 < pos.size(); ++i) {
    const double d0 = pos[1] - pos[0], di = pos[i + 1] - pos[i];
    if (std::abs(di) < 1e-6)
      throw InputError(dir + ": duplicate slice position " + std::to_string(pos[i]) + " mm");
    if (std::abs(di - d0) > 0.01 * std::abs(d0) + 1e-3)
      throw InputError(dir + ": irregular slice spacing (" + std::to_string(d0) + " mm, then " +
                       std::to_string(di) + " mm at slice " + std::to_string(i) +
                       "): missing slices? resample the series first");
  }
  PlainVolume v = from_itk(reader->GetOutput(), dir);
  v.modality = dicom_tag(*(*dicts)[0], "0008|0060");
  while (!v.modality.empty() && v.modality.back() == ' ') v.modality.pop_back();
  return v;
}

template <class T>
void write_with(const FloatImage* img, itk::ImageIOBase* io, const std::string& file) {
  using Out = itk::Image<T, 3>;
  auto out = Out::New();
  out->CopyInformation(img);
  out->SetRegions(img->GetLargestPossibleRegion());
  out->Allocate();
  const float* s = img->GetBufferPointer();
  const size_t n = img->GetLargestPossibleRegion().GetNumberOfPixels();
  std::transform(s, s + n, out->GetBufferPointer(), [](float x) { return T(x); });
  auto w = itk::ImageFileWriter<Out>::New();
  w->SetImageIO(io);
  w->SetFileName(file);
  w->SetInput(out);
  w->UseCompressionOn();
  w->Update();
}

bool fits_int16(const PlainVolume& v) {
  return std::all_of(v.voxels.begin(), v.voxels.end(),
                     [](float x) { return x == std::round(x) && x >= -32768 && x <= 32767; });
}

}  // namespace

PlainVolume itk_read_dicom_series(const std::string& dir) {
  try {
    LibraryMessages messages;
    PlainVolume v = read_series_impl(dir);
    v.notes = messages.take(dir);
    return v;
  } catch (const itk::ExceptionObject& e) {
    throw InputError(dir + ": cannot read the DICOM series: " + std::string(e.GetDescription()));
  }
}

PlainVolume itk_read_file(const std::string& path) {
  quiet_libraries();
  auto io = io_for(path);
  if (!io)
    throw InputError(path + ": unknown volume format (use a DICOM directory, .dcm, .nii, .nii.gz, "
                            ".nrrd, .mha, .mhd or .inv3)");
  std::error_code ec;
  if (fs::file_size(path, ec) == 0) throw InputError(path + ": file is empty");
  check_volume_file(path);
  const bool dicom = dynamic_cast<itk::GDCMImageIO*>(io.GetPointer()) != nullptr;
  const std::string bytes = dicom ? read_file(path) : std::string();
  if (dicom) refuse_dicom_without_image(bytes, path);
  LibraryMessages messages;  // from the first look at the file to the last voxel
  if (!io->CanReadFile(path.c_str())) {
    if (dicom) explain_unreadable_dicom(bytes, path);
    throw InputError(path + ": not a valid " + io->GetNameOfClass() + " file (wrong magic or header)");
  }
  if (dicom) check_dicom_pixel_data(bytes, path);
  try {
    io->SetFileName(path);
    io->ReadImageInformation();
    PlainVolume v = stored_as_int16(io) ? read_as<itk::Image<int16_t, 3>>(io, path) : read_as<FloatImage>(io, path);
    if (auto* g = dynamic_cast<itk::GDCMImageIO*>(io.GetPointer())) {
      v.modality = dicom_tag(g->GetMetaDataDictionary(), "0008|0060");
      while (!v.modality.empty() && v.modality.back() == ' ') v.modality.pop_back();
    }
    v.notes = messages.take(path);
    return v;
  } catch (const itk::ExceptionObject& e) {
    if (dicom) explain_unreadable_dicom(bytes, path);
    throw InputError(path + ": cannot read volume: " + std::string(e.GetDescription()));
  }
}

void itk_write_file(const PlainVolume& vol, const std::string& path) {
  const std::string p = lower_case(path);
  if (p.ends_with(".mhd") || p.ends_with(".nhdr"))
    throw InputError(path + ": header+data pairs cannot be written atomically; use .mha or .nrrd");
  auto io = io_for(path);
  if (!io || p.ends_with(".dcm"))
    throw InputError(path + ": unknown volume output format (use .nii, .nii.gz, .nrrd or .mha)");
  auto img = to_itk(vol);
  AtomicFile out(path);
  try {
    if (fits_int16(vol)) write_with<int16_t>(img, io, out.temp_path());
    else write_with<float>(img, io, out.temp_path());
  } catch (const itk::ExceptionObject& e) {
    throw InputError(path + ": cannot write volume: " + std::string(e.GetDescription()));
  }
  out.commit();
}

void itk_write_dicom_series(const PlainVolume& vol, const std::string& dir) {
  if (!fits_int16(vol)) throw InputError(dir + ": DICOM output needs integer voxels in int16 range");
  fs::create_directories(dir);
  using Slice = itk::Image<int16_t, 3>;
  const std::string root = "1.2.826.0.1.3680043.8.498.";  // example root for generated UIDs
  const std::string study = root + "1", series = root + "1.1";
  for (int64_t k = 0; k < vol.dims[2]; ++k) {
    auto img = Slice::New();
    Slice::RegionType region;
    Slice::SizeType size = {{itk::SizeValueType(vol.dims[0]), itk::SizeValueType(vol.dims[1]), 1}};
    region.SetSize(size);
    img->SetRegions(region);
    Slice::SpacingType sp;
    Slice::PointType org;
    Slice::DirectionType d;
    for (int a = 0; a < 3; ++a) {
      sp[a] = vol.spacing[size_t(a)];
      // Origin of slice k: origin + direction * (0, 0, k * spacing_z).
      org[a] = vol.origin[size_t(a)] + vol.direction[size_t(3 * a + 2)] * double(k) * vol.spacing[2];
      for (int b = 0; b < 3; ++b) d(a, b) = vol.direction[size_t(3 * a + b)];
    }
    img->SetSpacing(sp);
    img->SetOrigin(org);
    img->SetDirection(d);
    img->Allocate();
    const float* src = &vol.voxels[size_t(vol.dims[0] * vol.dims[1] * k)];
    std::transform(src, src + vol.dims[0] * vol.dims[1], img->GetBufferPointer(),
                   [](float x) { return int16_t(x); });
    auto io = itk::GDCMImageIO::New();
    io->KeepOriginalUIDOn();
    itk::MetaDataDictionary& md = img->GetMetaDataDictionary();
    itk::EncapsulateMetaData<std::string>(md, "0008|0060", vol.modality.empty() ? "CT" : vol.modality);
    itk::EncapsulateMetaData<std::string>(md, "0020|000d", study);
    itk::EncapsulateMetaData<std::string>(md, "0020|000e", series);
    itk::EncapsulateMetaData<std::string>(md, "0008|0018", series + "." + std::to_string(k + 1));
    itk::EncapsulateMetaData<std::string>(md, "0020|0013", std::to_string(k + 1));
    itk::EncapsulateMetaData<std::string>(md, "0018|0050", std::to_string(vol.spacing[2]));
    itk::EncapsulateMetaData<std::string>(md, "0028|1052", "0");
    itk::EncapsulateMetaData<std::string>(md, "0028|1053", "1");
    io->SetMetaDataDictionary(md);
    char name[32];
    std::snprintf(name, sizeof name, "slice%04d.dcm", int(k));
    const std::string file = (fs::path(dir) / name).string();
    AtomicFile out(file);
    try {
      auto w = itk::ImageFileWriter<Slice>::New();
      w->SetImageIO(io);
      w->SetFileName(out.temp_path());
      w->SetInput(img);
      w->Update();
    } catch (const itk::ExceptionObject& e) {
      throw InputError(file + ": cannot write DICOM: " + std::string(e.GetDescription()));
    }
    out.commit();
  }
}

}  // namespace mpumesh
