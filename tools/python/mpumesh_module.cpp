// The Python module `mpumesh`: the pipeline (core/pipeline) on numpy arrays, with the
// options of `mpumesh run` by the same names (underscores for dashes; --spacing, the
// particles' spacing, is particle_spacing= since spacing= is the voxel size), parsed and
// checked by the command's own option definitions (tools/run_cli.h), so the two cannot drift.
//   run(image, /, spacing=, origin=, direction=, threshold=, progress=, **options) -> dict
//   remesh(vertices, faces, /, progress=, **options) -> dict
//   read_volume(path) -> (array, spacing, origin, direction)
//   write_mesh(path, mesh)
//   to_meshio(result) -> meshio.Mesh
// Arrays are in numpy's (z, y, x) order: volume[k, j, i] is voxel (i, j, k), i along x.
// `volume=True` adds the volume mesh (what `run --volume` writes) as arrays; `labels=`
// meshes a label map's labels into one complex (`run --labels`), as does remesh() a
// surface of several parts. Bad input raises ValueError, a stage that failed
// RuntimeError, with the CLI's messages. The GIL is released while the pipeline runs;
// `progress(event, text)` is called with ("begin", stage), ("end", stage) and
// ("note", line), a callback of three arguments with ("progress", stage, fraction) too.
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
#include "mesh/component_filter.h"
#include "mesh/voxel_grid.h"
#include "pipeline/complex_run.h"
#include "segment/label_map.h"
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

// The keywords as `mpumesh run` options, parsed by the command's definitions; returns
// whether volume=True asks for the volume mesh.
bool parse_options(RunCli& o, const py::dict& options) {
  CLI::App app{"mpumesh"};
  tools::add_run_parameters(&app, o);
  std::vector<std::string> args = {"mpumesh"};
  bool volume = false;
  for (const auto& [k, v] : options) {
    const std::string key = py::str(k).cast<std::string>();
    std::string flag = "--" + key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (key == "volume") {
      if (!py::isinstance<py::bool_>(v))
        throw InputError("volume: True or False (the volume mesh comes back as arrays: points, tetrahedra, region)");
      volume = v.cast<bool>();
      continue;
    }
    if (key == "separate" && py::isinstance<py::bool_>(v) && v.cast<bool>())
      throw InputError("separate: mpumesh gives one complex of the labels or parts; mesh a label on its own with "
                       "label=L");
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
  if (o.tet.background && !volume) throw InputError("volume_background: applies to volume=True");
  return volume;
}

// Forwards the stages and the notes (spelled as keywords) to the callback, and a long
// stage's fraction done to a callback that takes three arguments.
class PyObserver : public pipeline::Observer {
 public:
  explicit PyObserver(py::object callback) : callback_(std::move(callback)) {
    with_fraction_ = !callback_.is_none() && takes_three(callback_);
  }
  void begin(const std::string& stage) override {
    stage_ = stage;
    call("begin", stage);
  }
  void end() override { call("end", stage_); }
  void progress(const std::string& stage, double fraction) override {
    if (!with_fraction_) return;
    py::gil_scoped_acquire gil;
    callback_("progress", stage, fraction);
  }
  void note(const std::string& line) override { call("note", spell_options(line, tools::python_spelling())); }

 private:
  void call(const char* event, const std::string& text) {
    if (callback_.is_none()) return;
    py::gil_scoped_acquire gil;
    callback_(event, text);
  }
  // Whether f(event, stage, fraction) binds: a callback of two arguments gets no progress
  // events.
  static bool takes_three(const py::object& f) {
    try {
      py::module_::import("inspect").attr("signature")(f).attr("bind")(py::none(), py::none(), py::none());
      return true;
    } catch (const py::error_already_set&) {
      return false;
    }
  }
  py::object callback_;
  bool with_fraction_ = false;
  std::string stage_;
};

py::array_t<double> vectors(const std::vector<Eigen::Vector3d>& v) {
  py::array_t<double> a({py::ssize_t(v.size()), py::ssize_t(3)});
  auto w = a.mutable_unchecked<2>();
  for (size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) w(py::ssize_t(i), c) = v[i][c];
  return a;
}

// Rows of N integers as an n x N int64 array.
template <size_t N, class T>
py::array_t<int64_t> int_rows(const std::vector<std::array<T, N>>& rows) {
  py::array_t<int64_t> a({py::ssize_t(rows.size()), py::ssize_t(N)});
  auto w = a.mutable_unchecked<2>();
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t c = 0; c < N; ++c) w(py::ssize_t(i), py::ssize_t(c)) = int64_t(rows[i][c]);
  return a;
}

template <class T>
py::array_t<T> values(const std::vector<T>& v) {
  py::array_t<T> a(py::ssize_t(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// The volume mesh's arrays (`run --volume`'s content): points, tetrahedra, region, and
// its boundary triangles with the region each bounds (and a complex's label pairs).
void add_volume_mesh(py::dict& d, const TetMesh& t) {
  d["points"] = vectors(t.nodes);
  d["tetrahedra"] = int_rows<4>(t.tets);
  d["region"] = values(t.region);
  d["boundary"] = int_rows<3>(t.boundary);
  d["boundary_region"] = values(t.boundary_region);
  if (t.multi_material()) d["boundary_labels"] = int_rows<2>(t.boundary_labels);
}

py::object json_to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// The mesh as the dict `run` and `remesh` return (without the report).
py::dict mesh_dict(const TriangleMesh& m) {
  py::dict d;
  d["vertices"] = vectors(m.vertices);
  d["faces"] = int_rows<3>(m.triangles);
  if (!m.normals.empty()) {
    py::array_t<float> n({py::ssize_t(m.normals.size()), py::ssize_t(3)});
    auto nw = n.mutable_unchecked<2>();
    for (size_t i = 0; i < m.normals.size(); ++i)
      for (int c = 0; c < 3; ++c) nw(py::ssize_t(i), c) = m.normals[i][c];
    d["normals"] = n;
  }
  if (!m.face_labels.empty()) d["face_labels"] = int_rows<2>(m.face_labels);
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

// A run's setting: its options parsed, the backend opened on first need, the threads.
struct PyRun {
  PyRun(const char* kind, const py::dict& kwargs, py::object progress) : observer(std::move(progress)) {
    o.input = kind;  // only which kind of input it is
    o.output = "complex.ply";  // a complex's output format, never written
    volume = parse_options(o, kwargs);
    tools::CommonOptions common;
    common.quiet = true;
    options = tools::run_options(o, common, "");
    if (volume) options.volume_mesh = o.tet;
    options.quality = QualityOptions{};
    options.quality->self_intersections = o.self_intersections;
    options.spacing_figures = true;
    open = [this, common]() -> ComputeBackend& {
      if (!choice.backend) choice = tools::open_backend(o.backend, common, stages);
      return *choice.backend;
    };
  }
  // Calls `job` with the GIL released and the thread limit applied.
  template <class Job>
  auto call(Job&& job) {
    py::gil_scoped_release release;
    std::optional<tbb::global_control> threads;
    if (o.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, size_t(o.threads));
    return job();
  }

  RunCli o;
  bool volume = false;
  pipeline::RunOptions options;
  tools::Progress stages{true};  // the command's own stages (the backend)
  PyObserver observer;
  vk::BackendChoice choice;
  pipeline::BackendOpener open;
};

// One surface's run as the dict, with the report as `mpumesh run --report` writes it.
py::dict single_dict(const pipeline::RunResult& r, PyRun& run) {
  nlohmann::json j = tools::run_json(r, {"", "", &run.choice, tools::python_spelling()});
  j.erase("output");
  if (run.options.label > 0) j["label"] = run.options.label;
  j["stage_seconds"] = tools::stage_seconds_json(r.stage_seconds, run.stages);
  j["memory"] = tools::memory_json(r);
  py::dict d = mesh_dict(r.mesh);
  if (r.volume) add_volume_mesh(d, r.volume->mesh);
  d["report"] = json_to_python(j);
  return d;
}

// A complex's run as the dict: its triangles with face_labels, and the report as
// `mpumesh run --labels ... --report` writes it.
py::dict complex_dict(const pipeline::ComplexResult& r, PyRun& run, const std::string& input) {
  nlohmann::json j = tools::complex_run_json(r, input, {"", "", &run.choice, tools::python_spelling()});
  j.erase("output");
  j["stage_seconds"] = tools::stage_seconds_json({}, run.stages);
  py::dict d = mesh_dict(r.complex.mesh);
  if (r.volume) add_volume_mesh(d, r.volume->mesh);
  d["report"] = json_to_python(j);
  return d;
}

py::dict run_volume(const Volume& input, const py::dict& kwargs, py::object progress) {
  PyRun run("volume", kwargs, std::move(progress));
  if (run.o.labels.empty())
    return single_dict(run.call([&] { return pipeline::run_pipeline(input, run.options, run.open, &run.observer); }),
                       run);
  pipeline::RunOptions quiet = run.options;
  quiet.quality.reset();
  const std::vector<int64_t> todo =
      pipeline::labels_to_mesh(input.source, seg::parse_label_list(run.o.labels), seg::label_voxel_counts(input));
  return complex_dict(run.call([&] {
                        return pipeline::run_complex(input, todo, run.o.labels == "all", quiet, run.open,
                                                     &run.observer, [](pipeline::LabelRun&) {});
                      }),
                      run, input.source);
}

py::dict run_mesh(const TriangleMesh& input, const py::dict& kwargs, py::object progress) {
  PyRun run("mesh.ply", kwargs, std::move(progress));
  const std::string name = "mesh arrays";
  // As `mpumesh run MESH`: a marching-cubes surface is a scan's, remeshed as one.
  const int64_t parts = voxel_grid_spacing(input) ? 1 : count_parts(input);
  if (parts < 2)
    return single_dict(
        run.call([&] { return pipeline::run_pipeline(input, name, run.options, run.open, &run.observer); }), run);
  pipeline::RunOptions quiet = run.options;
  quiet.quality.reset();
  return complex_dict(
      run.call([&] { return pipeline::run_parts_complex(input, name, quiet, run.open, &run.observer); }), run, name);
}

py::dict run(const py::array& volume, const py::object& spacing, const py::object& origin,
             const py::object& direction, const py::object& threshold, py::object progress, const py::kwargs& kw) {
  py::dict options;
  for (const auto& [k, v] : kw) options[k] = v;
  if (!threshold.is_none()) options["threshold"] = threshold;
  return run_volume(volume_from_array(volume, spacing, origin, direction), options, std::move(progress));
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
  return run_mesh(mesh_from_arrays(vertices, faces), options, std::move(progress));
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
  if (mesh.contains("face_labels")) {
    const auto l = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(mesh["face_labels"]);
    if (!l || l.ndim() != 2 || l.shape(0) != py::ssize_t(m.triangles.size()) || l.shape(1) != 2)
      throw InputError(path + ": 'face_labels' must be m x 2, one pair per face");
    for (py::ssize_t i = 0; i < l.shape(0); ++i) m.face_labels.push_back({int32_t(l.at(i, 0)), int32_t(l.at(i, 1))});
  }
  check_writable(path);
  py::gil_scoped_release release;
  write_mesh(m, path);
}

// Column c of an n x 2 integer array, and a column of n copies of -1.
py::array_t<int64_t> column(const py::handle& rows, int c, const char* what) {
  const auto a = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(rows);
  if (!a || a.ndim() != 2 || a.shape(1) != 2) throw InputError(std::string("to_meshio: '") + what + "' must be n x 2");
  py::array_t<int64_t> out(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out.mutable_at(i) = a.at(i, c);
  return out;
}
py::array_t<int64_t> none_column(py::ssize_t n) {
  py::array_t<int64_t> out(n);
  std::fill(out.mutable_data(), out.mutable_data() + n, -1);
  return out;
}

// The surface's per-vertex array over `points`: the surface's vertices are the volume
// mesh's first nodes, the other nodes (inside) NaN.
py::array_t<float> over_points(const py::handle& per_vertex, py::ssize_t points, const char* what) {
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(per_vertex);
  if (!a || a.ndim() < 1 || a.ndim() > 2 || a.shape(0) > points)
    throw InputError(std::string("to_meshio: '") + what + "' must hold one value or row per vertex");
  const py::ssize_t width = a.ndim() == 2 ? a.shape(1) : 1;
  std::vector<py::ssize_t> shape = {points};
  if (a.ndim() == 2) shape.push_back(width);
  py::array_t<float> out(shape);
  std::fill(out.mutable_data(), out.mutable_data() + points * width, std::numeric_limits<float>::quiet_NaN());
  std::copy(a.data(), a.data() + a.size(), out.mutable_data());
  return out;
}

// Whether the surface's vertices are the volume mesh's first nodes, coordinate for
// coordinate (a volume mesh keeps its surface's vertices, in order, and adds nodes after).
bool vertices_lead_points(const py::handle& vertices, const py::handle& points) {
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
  const auto p = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  return v && p && v.ndim() == 2 && p.ndim() == 2 && v.shape(0) <= p.shape(0) &&
         std::equal(v.data(), v.data() + v.size(), p.data());
}

py::object to_meshio(const py::dict& r) {
  for (const char* key : {"vertices", "faces"})
    if (!r.contains(key)) throw InputError(std::string("to_meshio: the result has no '") + key + "'");
  const py::module_ meshio = py::module_::import("meshio");
  const bool tets = r.contains("tetrahedra");
  if (tets)
    for (const char* key : {"points", "boundary", "boundary_region", "region"})
      if (!r.contains(key)) throw InputError(std::string("to_meshio: the result has tetrahedra but no '") + key + "'");
  const py::object points = tets ? py::object(r["points"]) : py::object(r["vertices"]);
  const py::ssize_t n_points = py::len(points);
  py::list cells;
  py::dict cell_data, point_data;
  if (tets) {
    cells.append(py::make_tuple("triangle", r["boundary"]));
    cells.append(py::make_tuple("tetra", r["tetrahedra"]));
    py::list region;
    region.append(r["boundary_region"]);
    region.append(r["region"]);
    cell_data["region"] = region;
    if (r.contains("boundary_labels")) {
      const py::ssize_t n_tets = py::len(r["tetrahedra"]);
      for (int c = 0; c < 2; ++c) {
        py::list side;
        side.append(column(r["boundary_labels"], c, "boundary_labels"));
        side.append(none_column(n_tets));
        cell_data[c == 0 ? "label_a" : "label_b"] = side;
      }
    }
  } else {
    cells.append(py::make_tuple("triangle", r["faces"]));
    if (r.contains("face_labels"))
      for (int c = 0; c < 2; ++c) {
        py::list side;
        side.append(column(r["face_labels"], c, "face_labels"));
        cell_data[c == 0 ? "label_a" : "label_b"] = side;
      }
  }
  if (!tets || vertices_lead_points(r["vertices"], points))
    for (const char* key : {"normals", "k1", "k2", "K", "H"})
      if (r.contains(key)) point_data[key] = over_points(r[key], n_points, key);
  return meshio.attr("Mesh")(points, cells, py::arg("point_data") = point_data, py::arg("cell_data") = cell_data);
}

// The docstrings (help(mpumesh.run)): every key returned, with its shape and units.
constexpr const char* kResultKeys = R"(
Returns a dict:
  vertices      (n, 3) float64, mm: the surface's vertices (LPS)
  faces         (m, 3) int64: triangles, counter-clockwise seen from outside (a
                complex's from region label_a into label_b)
  normals       (n, 3) float32: unit outward normals of the fitted surface
  k1, k2        (n,) float32, 1/mm: principal curvatures, k1 >= k2
  K             (n,) float32, 1/mm^2: Gaussian curvature
  H             (n,) float32, 1/mm: mean curvature (positive on a ball)
  face_labels   (m, 2) int64, a complex only: the labels (a, b), a < b, each triangle
                separates, 0 the background
  report        dict: the content of `mpumesh run --report`
With volume=True, also the volume mesh (`run --volume`):
  points        (p, 3) float64, mm: its nodes; the surface's vertices are the first n
  tetrahedra    (t, 4) int64: positively oriented linear tetrahedra
  region        (t,) int32: each tetrahedron's region (a complex's: its label)
  boundary      (b, 3) int64: the boundary triangles, indices into points
  boundary_region (b,) int32: the region each bounds
  boundary_labels (b, 2) int64, a complex only: the labels (a, b) each separates)";

const std::string kRunDoc = std::string(R"(Mesh a volume. image: a numpy array in (z, y, x) order (image[k, j, i] is voxel (i, j, k));
spacing and origin in mm as (x, y, z); direction 3 x 3, its columns the physical
directions of x, y and z. Options: those of `mpumesh run`, by the same names with
underscores (particles=, label=, largest=, backend=, threads=, ...), except that
--spacing is particle_spacing=. labels="all" (or a list) meshes a label map's labels into
one multi-material complex; volume=True adds its volume mesh (volume_background=True:
the background's box too). progress(event, text) is called with ("begin", stage),
("end", stage) and ("note", line), and a progress(event, stage, fraction) of three
arguments also with ("progress", stage, fraction), fraction 0 to 1 of a long stage
(particles, triangulate, optimize, volume mesh; labels and parts: the loop around them);
an exception it raises stops the run.
)") + kResultKeys;

const std::string kRemeshDoc = std::string(R"(Remesh a closed, oriented surface mesh (vertices (n, 3) in mm, faces (m, 3)); a mesh of
two or more closed parts becomes one complex, a part for a label, as `mpumesh run MESH`
makes it. Options as for run().
)") + kResultKeys;

constexpr const char* kToMeshioDoc = R"(The result of run() or remesh() as a meshio.Mesh. Without a volume mesh: the vertices,
one "triangle" block, point data normals, k1, k2, K, H, and for a complex cell data
label_a and label_b. With one: its points, a "triangle" block (the boundary) and a "tetra"
block; cell data region (and label_a, label_b: -1 on the tetrahedra); the point data on
the surface's vertices, NaN at the nodes inside. meshio.write(path, mesh) to .vtu gives a
file that `mpumesh quality` and `mpumesh tetmesh` read.)";

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
  m.def("run", &run, py::arg("image"), py::pos_only(), py::kw_only(), py::arg("spacing"),
        py::arg("origin") = py::none(), py::arg("direction") = py::none(), py::arg("threshold") = py::none(),
        py::arg("progress") = py::none(), kRunDoc.c_str());
  m.def("remesh", &remesh, py::arg("vertices"), py::arg("faces"), py::pos_only(), py::kw_only(),
        py::arg("progress") = py::none(), kRemeshDoc.c_str());
  m.def("to_meshio", &to_meshio, py::arg("result"), kToMeshioDoc);
  m.def("read_volume", &read_volume_arrays, py::arg("path"),
        "Read a volume through the CLI's readers: (array in (z, y, x) order, spacing, origin, direction).");
  m.def("write_mesh", &write_mesh_dict, py::arg("path"), py::arg("mesh"),
        "Write a mesh dict (as run() returns it) to .ply, .stl, .obj or .off, as `mpumesh run` writes it (a "
        "complex's face_labels as the PLY faces' label_a and label_b).");
}
