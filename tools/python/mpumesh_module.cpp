// The Python module `mpumesh`: the pipeline (core/pipeline) on numpy arrays, with the
// options of `mpumesh run` by the same names (underscores for dashes; --spacing, the
// particles' spacing, is particle_spacing= since spacing= is the voxel size), parsed and
// checked by the command's own option definitions (tools/run_cli.h), so the two cannot drift.
//   run(volume, spacing=, origin=, direction=, threshold=, progress=, **options) -> dict
//   remesh(vertices, faces, progress=, **options) -> dict
//   read_volume(path) -> (array, spacing, origin, direction)
//   write_mesh(path, mesh)
// Arrays are in numpy's (z, y, x) order: volume[k, j, i] is voxel (i, j, k), i along x.
// Bad input raises ValueError, a stage that failed RuntimeError, with the CLI's messages.
// The GIL is released while the pipeline runs; `progress(event, text)` is called with
// ("begin", stage), ("end", stage) and ("note", line).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/global_control.h>

#include <optional>

#include "cli_util.h"
#include "common/error.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "common/option_names.h"
#include "option_spelling.h"
#include "progress.h"
#include "run_json.h"
#include "run_cli.h"

namespace py = pybind11;

namespace mpumesh::python {
namespace {

using tools::RunCli;

// A keyword's value as the command line writes it: True as a bare flag, a (LO, HI) pair
// as LO:HI, a list as A,B,C.
std::string option_text(const std::string& key, const py::handle& v) {
  auto number = [](const py::handle& x) { return py::str(x).cast<std::string>(); };
  if (py::isinstance<py::tuple>(v) || py::isinstance<py::list>(v)) {
    const std::string sep = key == "threshold" || key == "window" ? ":" : ",";
    std::string out;
    for (const py::handle x : v) out += (out.empty() ? "" : sep) + number(x);
    return out;
  }
  return number(v);
}

// The command line's "--some-option" in a message as the keyword some_option.
std::string keyword_names(std::string text) {
  for (size_t at; (at = text.find("--")) != std::string::npos;) {
    text.erase(at, 2);
    for (size_t i = at; i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '-'); ++i)
      if (text[i] == '-') text[i] = '_';
  }
  return text;
}

// The keywords as `mpumesh run` options, parsed by the command's definitions.
void parse_options(RunCli& o, const py::dict& options) {
  CLI::App app{"mpumesh"};
  tools::add_run_parameters(&app, o);
  std::vector<std::string> args = {"mpumesh"};
  for (const auto& [k, v] : options) {
    const std::string key = py::str(k).cast<std::string>();
    std::string flag = "--" + key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (key == "labels") throw InputError("labels: mpumesh.run meshes one label; call it once per label with label=L");
    // `spacing` is the voxel size here; the particles' spacing (--spacing) is particle_spacing.
    if (key == "spacing") throw InputError("spacing: the particles' spacing is particle_spacing= (mm)");
    if (key == "particle_spacing") flag = "--spacing";
    if (py::isinstance<py::bool_>(v)) {
      if (v.cast<bool>()) args.push_back(flag);
      else if (app.get_option_no_throw("--no-" + flag.substr(2))) args.push_back("--no-" + flag.substr(2));
      continue;
    }
    args.push_back(flag);
    args.push_back(option_text(key, v));
  }
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    throw InputError("mpumesh: " + keyword_names(e.what()));
  }
}

// Forwards the stages and the notes (spelled as keywords) to the callback.
class PyObserver : public pipeline::Observer {
 public:
  explicit PyObserver(py::object callback) : callback_(std::move(callback)) {}
  void begin(const std::string& stage) override {
    stage_ = stage;
    call("begin", stage);
  }
  void end() override { call("end", stage_); }
  void note(const std::string& line) override { call("note", spell_options(line, tools::python_spelling())); }

 private:
  void call(const char* event, const std::string& text) {
    if (callback_.is_none()) return;
    py::gil_scoped_acquire gil;
    callback_(event, text);
  }
  py::object callback_;
  std::string stage_;
};

py::array_t<double> vectors(const std::vector<Eigen::Vector3d>& v) {
  py::array_t<double> a({py::ssize_t(v.size()), py::ssize_t(3)});
  auto w = a.mutable_unchecked<2>();
  for (size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) w(py::ssize_t(i), c) = v[i][c];
  return a;
}

py::object json_to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// The mesh as the dict `run` and `remesh` return (without the report).
py::dict mesh_dict(const TriangleMesh& m) {
  py::dict d;
  d["vertices"] = vectors(m.vertices);
  py::array_t<int64_t> f({py::ssize_t(m.triangles.size()), py::ssize_t(3)});
  auto fw = f.mutable_unchecked<2>();
  for (size_t i = 0; i < m.triangles.size(); ++i)
    for (int c = 0; c < 3; ++c) fw(py::ssize_t(i), c) = m.triangles[i][size_t(c)];
  d["faces"] = f;
  if (!m.normals.empty()) {
    py::array_t<float> n({py::ssize_t(m.normals.size()), py::ssize_t(3)});
    auto nw = n.mutable_unchecked<2>();
    for (size_t i = 0; i < m.normals.size(); ++i)
      for (int c = 0; c < 3; ++c) nw(py::ssize_t(i), c) = m.normals[i][c];
    d["normals"] = n;
  }
  if (!m.curvature.empty()) {
    const char* names[4] = {"k1", "k2", "K", "H"};
    for (int c = 0; c < 4; ++c) {
      py::array_t<float> k(py::ssize_t(m.curvature.size()));
      auto kw = k.mutable_unchecked<1>();
      for (size_t i = 0; i < m.curvature.size(); ++i) kw(py::ssize_t(i)) = m.curvature[i][size_t(c)];
      d[names[c]] = k;
    }
  }
  return d;
}

Eigen::Vector3d triple(const py::object& v, const char* what, bool positive) {
  std::vector<double> x;
  try {
    x = v.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
  }
  if (x.size() != 3) throw InputError(std::string(what) + ": three numbers (x, y, z) are needed");
  for (const double c : x)
    if (!std::isfinite(c) || (positive && !(c > 0)))
      throw InputError(std::string(what) + ": " + (positive ? "every value must be above 0" : "not finite"));
  return {x[0], x[1], x[2]};
}

Volume volume_from_array(const py::array& array, const py::object& spacing, const py::object& origin,
                         const py::object& direction) {
  if (array.ndim() != 3) throw InputError("volume: a 3-D array in (z, y, x) order is needed, not " +
                                          std::to_string(array.ndim()) + "-D");
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a) throw InputError("volume: the array's values are not numbers");
  Volume v;
  v.dims = {int64_t(a.shape(2)), int64_t(a.shape(1)), int64_t(a.shape(0))};
  v.spacing = triple(spacing, "spacing", true);
  v.origin = origin.is_none() ? Eigen::Vector3d::Zero() : triple(origin, "origin", false);
  if (!direction.is_none()) {
    std::vector<std::vector<double>> d;
    try {
      d = direction.cast<std::vector<std::vector<double>>>();
    } catch (const py::cast_error&) {
    }
    if (d.size() != 3 || d[0].size() != 3 || d[1].size() != 3 || d[2].size() != 3)
      throw InputError("direction: a 3 x 3 matrix is needed (its columns the physical directions of x, y, z)");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) v.direction(r, c) = d[size_t(r)][size_t(c)];
  }
  v.voxels.assign(a.data(), a.data() + a.size());
  v.source = "volume array";
  validate_volume(v, v.source);
  require_finite_voxels(v, v.source);
  return v;
}

// Runs the pipeline with the GIL released, and the report as `mpumesh run --report` writes it.
template <class Input>
py::dict run_on(const Input& input, const py::dict& kwargs, py::object progress, bool is_mesh) {
  RunCli o;
  o.input = is_mesh ? "mesh.ply" : "volume";  // only which kind of input it is
  parse_options(o, kwargs);
  tools::CommonOptions common;
  common.quiet = true;
  pipeline::RunOptions options = tools::run_options(o, common, "");
  options.quality = QualityOptions{};
  options.quality->self_intersections = o.self_intersections;
  options.spacing_figures = true;
  tools::Progress stages(true);  // the command's own stages (the backend)
  PyObserver observer(std::move(progress));
  vk::BackendChoice choice;
  pipeline::RunResult r;
  {
    py::gil_scoped_release release;
    std::optional<tbb::global_control> threads;
    if (o.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, size_t(o.threads));
    const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
      choice = tools::open_backend(o.backend, common, stages);
      return *choice.backend;
    };
    if constexpr (std::is_same_v<Input, Volume>) r = pipeline::run_pipeline(input, options, open, &observer);
    else r = pipeline::run_pipeline(input, "mesh arrays", options, open, &observer);
  }
  nlohmann::json j = tools::run_json(r, {"", "", &choice, tools::python_spelling()});
  j.erase("output");
  if (options.label > 0) j["label"] = options.label;
  j["stage_seconds"] = tools::stage_seconds_json(r.stage_seconds, stages);
  j["memory"] = tools::memory_json(r);
  py::dict d = mesh_dict(r.mesh);
  d["report"] = json_to_python(j);
  return d;
}

py::dict run(const py::array& volume, const py::object& spacing, const py::object& origin,
             const py::object& direction, const py::object& threshold, py::object progress, const py::kwargs& kw) {
  py::dict options;
  for (const auto& [k, v] : kw) options[k] = v;
  if (!threshold.is_none()) options["threshold"] = threshold;
  return run_on(volume_from_array(volume, spacing, origin, direction), options, std::move(progress), false);
}

TriangleMesh mesh_from_arrays(const py::array& vertices, const py::array& faces) {
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
  const auto f = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(faces);
  if (!v || v.ndim() != 2 || v.shape(1) != 3) throw InputError("vertices: an n x 3 array of numbers is needed");
  if (!f || f.ndim() != 2 || f.shape(1) != 3) throw InputError("faces: an m x 3 array of vertex indices is needed");
  TriangleMesh m;
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    m.vertices.emplace_back(v.at(i, 0), v.at(i, 1), v.at(i, 2));
    if (!m.vertices.back().allFinite()) throw InputError("vertices: vertex " + std::to_string(i) + " is not finite");
  }
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    std::array<uint32_t, 3> t{};
    for (int c = 0; c < 3; ++c) {
      const int64_t x = f.at(i, c);
      if (x < 0 || x >= int64_t(m.vertices.size()))
        throw InputError("faces: face " + std::to_string(i) + " names vertex " + std::to_string(x) + ", out of range");
      t[size_t(c)] = uint32_t(x);
    }
    m.triangles.push_back(t);
  }
  return m;
}

py::dict remesh(const py::array& vertices, const py::array& faces, py::object progress, const py::kwargs& kw) {
  py::dict options;
  for (const auto& [k, v] : kw) options[k] = v;
  return run_on(mesh_from_arrays(vertices, faces), options, std::move(progress), true);
}

py::tuple read_volume_arrays(const std::string& path) {
  Volume v;
  {
    py::gil_scoped_release release;
    v = read_volume(path);
  }
  py::array_t<float> a({py::ssize_t(v.dims[2]), py::ssize_t(v.dims[1]), py::ssize_t(v.dims[0])});
  std::copy(v.voxels.begin(), v.voxels.end(), a.mutable_data());
  py::array_t<double> d({py::ssize_t(3), py::ssize_t(3)});
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d.mutable_at(r, c) = v.direction(r, c);
  return py::make_tuple(a, py::make_tuple(v.spacing.x(), v.spacing.y(), v.spacing.z()),
                        py::make_tuple(v.origin.x(), v.origin.y(), v.origin.z()), d);
}

void write_mesh_dict(const std::string& path, const py::dict& mesh) {
  if (!mesh.contains("vertices") || !mesh.contains("faces"))
    throw InputError(path + ": the mesh needs 'vertices' and 'faces'");
  TriangleMesh m = mesh_from_arrays(mesh["vertices"], mesh["faces"]);
  if (mesh.contains("normals")) {
    const auto n = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(mesh["normals"]);
    if (!n || n.ndim() != 2 || n.shape(0) != py::ssize_t(m.vertices.size()) || n.shape(1) != 3)
      throw InputError(path + ": 'normals' must be n x 3, one per vertex");
    for (py::ssize_t i = 0; i < n.shape(0); ++i) m.normals.emplace_back(n.at(i, 0), n.at(i, 1), n.at(i, 2));
  }
  if (mesh.contains("K")) {
    std::array<py::array_t<float, py::array::c_style | py::array::forcecast>, 4> k;
    const char* names[4] = {"k1", "k2", "K", "H"};
    for (int c = 0; c < 4; ++c) {
      if (!mesh.contains(names[c])) throw InputError(path + ": the curvatures need k1, k2, K and H");
      k[size_t(c)] = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(mesh[names[c]]);
      if (!k[size_t(c)] || k[size_t(c)].size() != py::ssize_t(m.vertices.size()))
        throw InputError(path + ": '" + names[c] + "' must hold one value per vertex");
    }
    for (size_t i = 0; i < m.vertices.size(); ++i)
      m.curvature.push_back({k[0].data()[i], k[1].data()[i], k[2].data()[i], k[3].data()[i]});
  }
  check_writable(path);
  py::gil_scoped_release release;
  write_mesh(m, path);
}

}  // namespace
}  // namespace mpumesh::python

PYBIND11_MODULE(mpumesh, m) {
  using namespace mpumesh::python;
  m.doc() = "mpumesh: smooth, closed, adaptive triangle meshes from CT/MR volumes and label maps";
  m.attr("__version__") = MPUMESH_VERSION;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const mpumesh::InputError& e) {
      PyErr_SetString(PyExc_ValueError, mpumesh::spell_options(e.what(), mpumesh::tools::python_spelling()).c_str());
    } catch (const mpumesh::NumericalError& e) {
      PyErr_SetString(PyExc_RuntimeError, mpumesh::spell_options(e.what(), mpumesh::tools::python_spelling()).c_str());
    } catch (const mpumesh::InternalError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  m.def("run", &run, py::arg("volume"), py::kw_only(), py::arg("spacing"), py::arg("origin") = py::none(),
        py::arg("direction") = py::none(), py::arg("threshold") = py::none(), py::arg("progress") = py::none(),
        "Mesh a volume (numpy array in (z, y, x) order; spacing, origin in mm as (x, y, z); direction 3 x 3, its "
        "columns the physical directions of x, y, z). Options: those of `mpumesh run`, by the same names with "
        "underscores (particles=, label=, largest=, backend=, threads=, ...), except that --spacing is "
        "particle_spacing=. Returns a "
        "dict: vertices (n x 3, mm), faces (m x 3), normals (n x 3), k1, k2, K, H (n), report (the JSON report).");
  m.def("remesh", &remesh, py::arg("vertices"), py::arg("faces"), py::kw_only(), py::arg("progress") = py::none(),
        "Remesh a closed, oriented surface mesh; options and result as for run().");
  m.def("read_volume", &read_volume_arrays, py::arg("path"),
        "Read a volume through the CLI's readers: (array in (z, y, x) order, spacing, origin, direction).");
  m.def("write_mesh", &write_mesh_dict, py::arg("path"), py::arg("mesh"),
        "Write a mesh dict (as run() returns it) to .ply, .stl, .obj or .off, as `mpumesh run` writes it.");
}
