// The dense material-pair table: for each (material a, material b) the
// contact model and its derived parameters, computed once at set-up (or when
// the script changes a parameter), never inside the force loop.
#pragma once

#include <string>
#include <tuple>
#include <vector>

#include "contact/models.hpp"

namespace granule {

template <typename Tuple>
struct ParamVectors;
template <typename... Ms>
struct ParamVectors<std::tuple<Ms...>> {
  using type = std::tuple<std::vector<typename Ms::Params>...>;
};

class PairTable {
 public:
  struct Entry {
    int model = -1;  // index into ContactModels; -1: no contact law declared
    int slot = -1;   // index into that model's parameter vector
  };

  void resize(int material_count) {
    std::vector<Entry> grown(static_cast<std::size_t>(material_count) * material_count);
    for (int a = 0; a < materials_; ++a)
      for (int b = 0; b < materials_; ++b) grown[a * material_count + b] = at(a, b);
    table_ = std::move(grown);
    materials_ = material_count;
  }
  int material_count() const { return materials_; }

  const Entry& at(int a, int b) const {
    return table_[static_cast<std::size_t>(a) * materials_ + b];
  }
  // Does any pair of materials have its contacts under `model`?
  bool uses(int model) const {
    for (const Entry& e : table_)
      if (e.model == model) return true;
    return false;
  }

  // Declares (or replaces) the law between a and b. `values` must already be resolved.
  void set(int a, int b, int model, const ParamValues& values, const PairMaterials& materials);
  // Changes some parameters of an existing law (friction or surface-energy ramps).
  void update(int a, int b, const ParamValues& changes, const std::string& context,
              const PairMaterials& materials);
  const ParamValues& values(int a, int b) const { return values_[key(a, b)]; }
  // The same as they act, for reports (a header, sim:contact_parameters): a value
  // that stands for one taken from the materials (thornton_jkr's surface_energy -1)
  // replaced by it. `materials` indexed as the table's.
  ParamValues values_in_effect(int a, int b, const std::vector<Material>& materials) const;

  template <int I>
  const std::vector<typename ContactModelAt<I>::Params>& params() const {
    return std::get<I>(params_);
  }

 private:
  std::size_t key(int a, int b) const { return static_cast<std::size_t>(a) * materials_ + b; }
  int materials_ = 0;
  std::vector<Entry> table_;
  std::vector<ParamValues> values_{};
  typename ParamVectors<ContactModels>::type params_;
};

}  // namespace granule
