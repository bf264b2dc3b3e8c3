// Spatial decomposition of a scene over ranks by recursive coordinate
// bisection (RCB): the domain box is cut across its longest side at the
// weighted median of the points' costs, and each half again, until there is
// one box per rank. RCB rather than a brick grid because the scenes are
// uneven by nature (a settled bed under empty space, the Mechanofusion charge
// thrown against the chamber wall): a grid balances such a scene only with
// many more boxes than ranks, where RCB balances any rank count with one box
// each and re-cuts cheaply from measured cost (as Zoltan's and LAMMPS's
// `balance rcb` do).
//
// Everything here is a pure function of its inputs (points, weights, ids):
// every rank computes the same cut from the same gathered data, so no rank has
// to broadcast it, and a re-run gives the same boxes.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace granule::parallel {

template <int D>
struct Box {
  Vec<D> lo = Vec<D>::Zero(), hi = Vec<D>::Zero();  // m; a point x is inside when lo <= x < hi
  bool contains(const Vec<D>& x) const {
    for (int a = 0; a < D; ++a)
      if (!(x[a] >= lo[a] && x[a] < hi[a])) return false;
    return true;
  }
  double volume() const {
    double v = 1;
    for (int a = 0; a < D; ++a) v *= hi[a] - lo[a];
    return v;
  }
  // Euclidean distance from x to the box (0 inside).
  double distance(const Vec<D>& x) const {
    double s = 0;
    for (int a = 0; a < D; ++a) {
      const double d = x[a] < lo[a] ? lo[a] - x[a] : (x[a] >= hi[a] ? x[a] - hi[a] : 0.0);
      s += d * d;
    }
    return std::sqrt(s);
  }
};

// One cut of the bisection tree: ranks [first, first + count) split into
// [first, first + left) below `position` along `axis` and the rest above.
struct Cut {
  int first = 0, count = 0, left = 0;
  int axis = 0;
  double position = 0;  // m
};

template <int D>
struct Decomposition {
  Box<D> domain;                    // the whole scene
  std::array<bool, D> periodic{};   // axes on which the domain wraps
  std::vector<Box<D>> boxes;        // one per rank
  std::vector<Cut> cuts;            // the bisection tree, parents before children
  std::vector<double> rank_weight;  // the cost each box received when it was cut

  int ranks() const { return static_cast<int>(boxes.size()); }
  // The rank whose box holds x (x wrapped into the domain on periodic axes;
  // outside the domain on open axes, the nearest box along the cut tree).
  int owner(const Vec<D>& x) const;
  // Largest rank cost over the mean (1 = perfectly balanced).
  double imbalance() const;
  // "rcb: 4 boxes, imbalance 1.02; cuts x = 0.012, y = -0.003 ..." for the run header.
  std::string describe() const;
};

// Cuts `domain` into `ranks` boxes so that each holds an equal share of the
// total weight (up to one point's weight per cut). Points with equal
// coordinates are ordered by id, so the result does not depend on the order
// the points are given in. weights may be empty (every point weighs 1).
template <int D>
Decomposition<D> bisect(const Box<D>& domain, const std::array<bool, D>& periodic, int ranks,
                        const std::vector<Vec<D>>& points, const std::vector<double>& weights,
                        const std::vector<std::int64_t>& ids);

// x wrapped into the domain along its periodic axes.
template <int D>
Vec<D> wrap(const Decomposition<D>& d, Vec<D> x);

}  // namespace granule::parallel
