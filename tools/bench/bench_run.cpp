// Benchmark: the whole job on the sample CT (bone at 226 HU) against its peers, all
// measured in the same run on the same volume: the marching-cubes baseline (`mpumesh mc`),
// the original MPU mesh (`mpumesh polygonize` of our fit) and CGAL Mesh_3 on the gray
// image with manifold() (tools/bench/cgal_mesh3_peer.h), sequential and in its parallel
// mode on the same threads as ours; the time ratio that counts is against the faster of
// the two. For each: triangles, time,
// topology, triangle quality, smoothness (mean dihedral angle) and fidelity to the
// marching-cubes surface (mean and 99th-percentile distances both ways, and bones
// missing: marching-cubes components of more than 100 triangles whose vertices lie
// farther than 2 mm from the mesh, median). Ours is the pipeline `mpumesh run VOLUME
// --threshold T --quiet` runs, timed from reading the file to the checked mesh (the peers
// get the volume already read; the ratio to Mesh_3 is also given with the read added to
// its time, as a program of a user's would read it), on the backend `auto` picks.
// With ROUNDS > 1, ours and Mesh_3 run in turn that many times (the meshes of the first
// round are the ones measured; ours is the same mesh every round, Mesh_3's differs a
// little): the times are the medians, and each round's ratio is printed too, since this
// machine's speed drifts within minutes and one round's ratio can be off by a third.
// EPS (mm) sets our fit's error bound, as `mpumesh run --eps` does; absent or 0, ours
// takes the noise-aware tolerance, as the product does by default. (With it, the time a
// coarser fit saves is measured against the fidelity it costs.)
// Usage:
//   mpumesh_bench_run VOLUME [THRESHOLD] [PARTICLES] [FACET_SIZE] [FACET_DISTANCE] [cpu|gpu|auto] [ROUNDS] [EPS]
#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "cgal_mesh3_peer.h"
#include "mesh_rows.h"
#include "cpu/cpu_backend.h"
#include "io/volume_io.h"
#include "mc/marching_cubes.h"
#include "mesh/cgal_geometry.h"
#include "mesh/quality.h"
#include "mpu/polygonize.h"
#include "pipeline/run_pipeline.h"
#include "truth_rows.h"
#include "vulkan_backend.h"

using namespace mpumesh;

namespace {

using Clock = std::chrono::steady_clock;
double sec_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Each stage's time (summed over repeats, as the count raises repeat the sampling).
class StageTimes : public pipeline::Observer {
 public:
  void begin(const std::string& stage) override { stage_ = stage, t0_ = Clock::now(); }
  void end() override { seconds_[stage_] += sec_since(t0_); }
  double at(const std::string& stage) const {
    const auto it = seconds_.find(stage);
    return it == seconds_.end() ? 0.0 : it->second;
  }

 private:
  std::string stage_;
  Clock::time_point t0_;
  std::map<std::string, double> seconds_;
};

// A Mesh_3 peer: its parameters and each round's time and triangles.
struct Peer {
  bench::Mesh3Params params;
  std::vector<double> seconds;
  std::vector<size_t> triangles;
};

// Rounds 2 to `rounds` of ours and the peers in turn (the first is done); the medians,
// ours first.
template <class RunOurs>
std::vector<double> rounds_in_turn(int rounds, const TriangleMesh& ours, RunOurs&& run_ours, const Volume& vol,
                                   std::vector<double>& ours_s, std::vector<Peer>& peers) {
  for (int k = 1; k < rounds; ++k) {
    StageTimes unused;
    const pipeline::RunResult again = run_ours(unused, ours_s[size_t(k)]);
    if (again.mesh.triangles != ours.triangles) std::printf("warning: round %d made another mesh of ours\n", k + 1);
    for (Peer& p : peers) {
      const bench::Mesh3Result cg_again = bench::cgal_mesh3(vol, p.params);
      p.seconds.push_back(cg_again.seconds);
      p.triangles.push_back(cg_again.mesh.triangles.size());
    }
  }
  std::vector<double> medians = {median(ours_s)};
  for (const Peer& p : peers) medians.push_back(median(p.seconds));
  if (rounds > 1) {
    // (Mesh_3's initial points are random: its triangles differ a little between rounds.)
    std::printf("%d rounds, in turn (Mesh_3's triangles in brackets; the ratio against the faster Mesh_3):\n", rounds);
    for (int k = 0; k < rounds; ++k) {
      const size_t i = size_t(k);
      std::printf("  ours %.2f s, Mesh_3 sequential %.2f s [%zu], parallel %.2f s [%zu]: %.2f\n", ours_s[i],
                  peers[0].seconds[i], peers[0].triangles[i], peers[1].seconds[i], peers[1].triangles[i],
                  ours_s[i] / std::min(peers[0].seconds[i], peers[1].seconds[i]));
    }
    std::printf("medians: ours %.2f s, CGAL Mesh_3 sequential %.2f s, parallel %.2f s (the table's times; its figures "
                "are the first round's)\n",
                medians[0], medians[1], medians[2]);
  }
  return medians;
}

// Mesh_3's first round: sequential, then in its parallel mode on TBB's threads (as many as
// ours); `peers` gets both, with this round's time and triangles.
std::vector<bench::Mesh3Result> first_mesh3_rounds(const Volume& vol, const bench::Mesh3Params& m3,
                                                   std::vector<Peer>& peers) {
  peers.assign(2, Peer{m3, {}, {}});
  peers[1].params.parallel = true;
  std::vector<bench::Mesh3Result> cg;
  for (Peer& p : peers) {
    cg.push_back(bench::cgal_mesh3(vol, p.params));
    p.seconds.push_back(cg.back().seconds);
    p.triangles.push_back(cg.back().mesh.triangles.size());
  }
  std::printf("CGAL Mesh_3: facet_angle %g, facet_size %g, facet_distance %g; sequential: %lld initial points, %.2f s; "
              "parallel (%d threads): %lld initial points, %.2f s\n",
              m3.facet_angle, m3.facet_size, m3.facet_distance, (long long)cg[0].initial_points, cg[0].seconds,
              tbb::this_task_arena::max_concurrency(), (long long)cg[1].initial_points, cg[1].seconds);
  return cg;
}

// Ours against each Mesh_3 and the faster, by the medians `med` (ours, sequential,
// parallel), in time and triangles.
void print_ratios(const TriangleMesh& ours, const std::vector<bench::Mesh3Result>& cg, const std::vector<double>& med,
                  int threads, double t_read) {
  const double t_ours = med[0], t_faster = std::min(med[1], med[2]);
  std::printf("\n(Mesh_3 seq.: CGAL Mesh_3 sequential; par. (N): in its parallel mode on N threads; ours runs on %d "
              "threads)\n",
              threads);
  std::printf("time ours / CGAL Mesh_3 sequential: %.2f; / parallel: %.2f; / the faster (%s): %.2f\n",
              t_ours / med[1], t_ours / med[2], med[2] < med[1] ? "parallel" : "sequential", t_ours / t_faster);
  std::printf("triangles ours / CGAL sequential: %.2f, / parallel: %.2f\n",
              double(ours.triangles.size()) / double(std::max<size_t>(cg[0].mesh.triangles.size(), 1)),
              double(ours.triangles.size()) / double(std::max<size_t>(cg[1].mesh.triangles.size(), 1)));
  // A user's Mesh_3 program reads the volume too (CGAL reads no .inv3 or DICOM series).
  std::printf("time ours / (the volume's read, %.2f s, + the faster CGAL Mesh_3): %.2f\n", t_read,
              t_ours / (t_read + t_faster));
}

}  // namespace

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s VOLUME [THRESHOLD] [PARTICLES] [FACET_SIZE] [FACET_DISTANCE] [cpu|gpu|auto] [ROUNDS] "
                 "[EPS]\n",
                 argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const double iso = argc > 2 ? std::stod(argv[2]) : 226;
  const int64_t particles = argc > 3 ? std::stoll(argv[3]) : 0;  // 0: the product's default
  bench::Mesh3Params m3;
  m3.iso = iso;
  if (argc > 4) m3.facet_size = std::stod(argv[4]);
  if (argc > 5) m3.facet_distance = std::stod(argv[5]);
  const int rounds = argc > 7 ? std::max(1, std::stoi(argv[7])) : 1;
  const double eps = argc > 8 ? std::stod(argv[8]) : 0.0;  // 0: the noise-aware tolerance

  auto t = Clock::now();
  const Volume vol = read_volume(path);  // for the peers
  const double t_read = sec_since(t);
  std::printf("volume %s: %lld x %lld x %lld, spacing %.3f x %.3f x %.3f mm, threshold %g\n", path.c_str(),
              (long long)vol.dims[0], (long long)vol.dims[1], (long long)vol.dims[2], vol.spacing.x(), vol.spacing.y(),
              vol.spacing.z(), iso);
  CpuBackend cpu;
  vk::BackendChoice choice = vk::make_backend(argc > 6 ? argv[6] : "auto");
  std::printf("ours on: %s%s\n", choice.backend->device().c_str(),
              choice.note.empty() ? "" : (" (" + choice.note + ")").c_str());

  t = Clock::now();
  const TriangleMesh mc_mesh = marching_cubes(vol, mc::ThresholdRange{iso}, cpu);
  const double t_mc = sec_since(t);

  // Ours: the pipeline `mpumesh run VOLUME --threshold T --quiet` runs (core/pipeline),
  // from reading the file to the checked mesh, without writing it.
  pipeline::RunOptions ro;
  ro.segment.method = seg::Method::kThreshold;  // --threshold alone
  ro.segment.threshold = mc::ThresholdRange{iso};
  ro.sample.particles = particles;  // 0: the product's default
  ro.fit.eps = eps;
  ro.quality.reset();               // --quiet and no report
  StageTimes times;
  auto run_ours = [&](StageTimes& st, double& seconds) {
    const auto t_all = Clock::now();
    pipeline::RunResult r = pipeline::run_pipeline(path, ro, [&]() -> ComputeBackend& { return *choice.backend; }, &st);
    seconds = sec_since(t_all);
    return r;
  };
  std::vector<double> ours_s(static_cast<size_t>(rounds));
  const pipeline::RunResult run = run_ours(times, ours_s[0]);
  const double t_ours_first = ours_s[0];
  const TriangleMesh& ours = run.mesh;
  const mpu::MpuSurface& surf = run.surface;
  const double t_seg = times.at("segment"), t_points = times.at("points"), t_fit = times.at("fit");
  std::printf("ours: read %.2f s, segment %.2f s, points %.2f s (%zu), fit %.2f s (%zu leaves, eps %.3f mm%s), "
              "particles %.2f s (%lld, %d iterations, %s), triangulate %.2f s (%lld repair points, %zu count raises): "
              "%.2f s\n",
              times.at("read volume"), t_seg, t_points, run.points, t_fit, surf.leaves.size(), run.fit.eps,
              run.derived.eps_given ? ", given" : "", times.at("particles"),
              (long long)run.sample.particles, run.sample.iterations, run.sample.converged ? "settled" : "at the cap",
              times.at("triangulate"), (long long)run.triangulation.repair_points, run.raises.size(), t_ours_first);

  t = Clock::now();
  const TriangleMesh poly = mpu::polygonize(surf, 0, cpu);
  const double t_poly = sec_since(t);

  std::vector<Peer> peers;
  const std::vector<bench::Mesh3Result> cg = first_mesh3_rounds(vol, m3, peers);
  const int threads = tbb::this_task_arena::max_concurrency();
  const std::vector<double> med = rounds_in_turn(rounds, ours, run_ours, vol, ours_s, peers);
  const double t_ours = med[0];

  std::vector<bench::Row> rows(5);
  rows[0] = {"ours (" + choice.backend->kind() + ")", &ours, t_ours};
  rows[1] = {"Mesh_3 seq.", &cg[0].mesh, med[1]};
  rows[2] = {fmt::format("Mesh_3 par. ({})", threads), &cg[1].mesh, med[2]};
  rows[3] = {"original MPU", &poly, t_poly + t_seg + t_points + t_fit};
  rows[4] = {"marching cubes", &mc_mesh, t_mc};
  for (size_t i = 0; i < rows.size(); ++i) bench::measure(rows[i], mc_mesh, i < 3);

  bench::print_rows(rows);
  print_ratios(ours, cg, med, threads, t_read);
  return 0;
}
