// The MPU fit's neighbour searches on a uniform grid of the points: every point strictly
// inside a ball (|p - q|² < r², the k-d tree's radius-search rule), and the k-th smallest
// squared distance from a point (how far a ball must grow to hold k points). Both give
// what nanoflann gives (the same set, the same k-th distance: the squared distance is
// summed in the same order), at a fraction of its cost on the fit's many small balls:
// the points are stored in cell order, coordinates apart, so a ball's cells are scanned
// as contiguous runs.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <utility>
#include <vector>

namespace mpumesh::mpu {

class BallSearch {
 public:
  // `cell`: the grid's cell size (mm), about the smallest ball radius; the grid is made
  // coarser where it would exceed 2^21 cells.
  BallSearch(const std::vector<Eigen::Vector3d>& pts, double cell);

  // Appends to `out` the ids of the points with |p - q|² < r2, in the grid's order (cells
  // by z, y, x, then the points of a cell by id): one order for every query, whatever its
  // radius.
  void ball(const Eigen::Vector3d& q, double r2, std::vector<uint32_t>& out) const;

  // The points within a radius of q, with their squared distances: what the searches
  // below collect, and what a grown ball is then taken from.
  struct Near {
    std::vector<std::pair<double, uint32_t>> points;  // (|p - q|², id), in the grid's order
    double radius = 0;                                // every point within it is listed
  };

  // The k-th smallest |p - q|² over all points (k >= 1, at most the point count),
  // searching outward from radius `start` (> 0); `near` keeps what was searched.
  double kth_distance2(const Eigen::Vector3d& q, size_t k, double start, Near& near) const;

  // The k nearest points (ids) in order of distance, when k + 1 points lie within
  // `radius` and that order is strict: no two of the k + 1 nearest at the same distance
  // (the k-d tree would break such a tie by its own visiting order). Returns false (and
  // leaves `ids` empty) otherwise: the k-d tree is the better search for points far from
  // every other.
  bool nearest_strict(const Eigen::Vector3d& q, size_t k, double radius, Near& near, std::vector<uint32_t>& ids) const;

 private:
  // Calls fn(first, last) for the runs of stored points in the cells that the box
  // [q - r, q + r] touches.
  template <class Fn>
  void for_runs(const Eigen::Vector3d& q, double r, Fn&& fn) const;
  // Calls fn(|p - q|², id) for the points of those runs, in the grid's order.
  template <class Fn>
  void for_distances(const Eigen::Vector3d& q, double r, Fn&& fn) const;
  // Fills `near` with every point within r of q.
  void collect(const Eigen::Vector3d& q, double r, Near& near) const;

  Eigen::Vector3d lo_;
  double inv_cell_ = 1;
  int64_t dims_[3] = {1, 1, 1};
  std::vector<uint32_t> start_;  // per cell, into the arrays below (cells + 1)
  std::vector<double> x_, y_, z_;
  std::vector<uint32_t> id_;
};

}  // namespace mpumesh::mpu
