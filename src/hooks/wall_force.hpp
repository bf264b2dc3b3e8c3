// Force on a wall (dissertation 4.4.1, the force on the inner piece): the sum
// of the contact normal forces N and of the tangential forces along the
// wall's direction of positive rotation (for a cylinder, a 2D polyline and a
// 3D mesh, about their axis; the magnitude of the summed tangential vector for
// a plane and the other walls), their time series averaged over
// windows, and long-time means since the diagnostic was attached. The summed
// force vector on the wall is kept too: a plane's tangential magnitude has no
// sign, so balances of forces (a bed's weight shared by floor and side walls,
// whose friction may push either way) are made with the vector.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

template <int D>
class WallForceDiagnostic final : public Diagnostic<D> {
 public:
  using V = Vec<D>;
  static constexpr const char* name = "wall_force";
  static constexpr const char* doc =
      "normal and tangential contact force on a wall (4.4.1): window-averaged series and "
      "long-time means";
  static OptionDocs own_options() {
    return {{"wall", "", "", "the wall's name", true},
            {"label", "", "", "group under /diagnostics ('': wall_force_<wall>)"}};
  }
  static constexpr Sampling::Defaults sampling_defaults{1, 1e-3};
  static OptionDocs options() {
    OptionDocs o = own_options();
    Sampling::add_option_docs(o, sampling_defaults);
    return o;
  }

  explicit WallForceDiagnostic(DiagnosticOptions& o) : Diagnostic<D>(name) {
    wall_name_ = o.string("wall", "");
    if (wall_name_.empty()) throw InputError(fmt::format("{}: give wall = '<name>'", o.context()));
    this->sampling_.read(o, sampling_defaults);
    label_ = o.string("label", "");
    if (label_.empty()) label_ = "wall_force_" + wall_name_;
  }

  typename Diagnostic<D>::Needs needs() const override { return {true, false}; }

  void attach_output(OutputSink* sink) override {
    sink_ = sink;
    if (!sink_) return;
    group_ = "diagnostics/" + label_;
    sink_->declare_series(group_, {"time", "normal_force", "tangential_force", "force_x", "force_y",
                                   "force_z", "samples"});
    sink_->write_attribute(group_, "wall", wall_name_);
    this->write_sampling_attributes(*sink_, group_);
    sink_->write_attribute(group_, "units", std::string("s, N, N, N, N, N, -"));
  }

  void sample(const StepView<D>& v) override {
    if (wall_ < 0 || wall_ >= static_cast<int>(v.walls.size())) wall_ = find_wall(v);
    const Wall<D>& w = v.walls[wall_];
    double normal = 0;
    V tangential = V::Zero(), total = V::Zero();
    double tangential_signed = 0;
    const auto& log = v.contacts;
    for (const std::uint32_t s : log.slots) {
      if (log.b[s] != -1 - wall_) continue;
      normal += log.normal_force[s];
      const V t_on_wall = -log.tangential[s];
      tangential += t_on_wall;
      total -= log.normal_force[s] * log.normal[s] + log.tangential[s];
      if (signed_tangential(w)) tangential_signed += t_on_wall.dot(rotation_sense(w, log, s));
    }
    const double tangential_value = signed_tangential(w) ? tangential_signed : tangential.norm();
    add(normal, tangential_value, total);
  }

  std::map<std::string, double> results() const override {
    const double n = total_samples_ > 0 ? total_samples_ : 1;
    std::map<std::string, double> out{{"mean_normal_force", sum_normal_ / n},
                                      {"mean_tangential_force", sum_tangential_ / n},
                                      {"samples", static_cast<double>(total_samples_)}};
    static constexpr const char* axis_names[] = {"mean_force_x", "mean_force_y", "mean_force_z"};
    const double nv = vector_samples_ > 0 ? vector_samples_ : 1;
    for (int k = 0; k < D; ++k) out[axis_names[k]] = sum_total_[k] / nv;
    return out;
  }

  const std::string& label() const override { return label_; }
  std::string describe() const override {
    return fmt::format("force on wall '{}' {}", wall_name_, this->sampling_.describe());
  }

  void save_own(DiagnosticStateWriter& w) const override {
    w.put_integers("counts", {wall_, window_samples_, total_samples_});
    std::vector<double> sums{window_normal_, window_tangential_, sum_normal_, sum_tangential_};
    sums.insert(sums.end(), window_total_.data(), window_total_.data() + D);
    w.put("sums", std::move(sums));
    std::vector<double> total(sum_total_.data(), sum_total_.data() + D);
    total.push_back(static_cast<double>(vector_samples_));
    w.put("sum_total", std::move(total));
  }
  void load_own(const DiagnosticStateReader& r) override {
    const auto counts = r.integers("counts", 3);
    if (counts[0] < -1 || counts[1] < 0 || counts[2] < counts[1])
      r.invalid("counts", "holds impossible counts");
    const auto sums = r.doubles("sums", 4 + D);
    wall_ = static_cast<int>(counts[0]);
    window_samples_ = counts[1], total_samples_ = counts[2];
    window_normal_ = sums[0], window_tangential_ = sums[1], sum_normal_ = sums[2];
    sum_tangential_ = sums[3];
    for (int k = 0; k < D; ++k) window_total_[k] = sums[4 + k];
    // Checkpoints written before the long-time vector was kept have no entry:
    // its mean then counts from the restart (its own sample count).
    sum_total_.setZero();
    vector_samples_ = 0;
    if (r.has("sum_total")) {
      const auto total = r.doubles("sum_total", D + 1);
      for (int k = 0; k < D; ++k) sum_total_[k] = total[k];
      vector_samples_ = static_cast<std::int64_t>(total[D]);
    }
  }

 private:
  std::string fingerprint() const override {
    return fmt::format("{}; wall {}; label {}", name, wall_name_, label_);
  }
  int find_wall(const StepView<D>& v) const {
    for (std::size_t w = 0; w < v.walls.size(); ++w)
      if (v.walls[w].name == wall_name_) return static_cast<int>(w);
    throw InputError(fmt::format("diagnostic 'wall_force': no wall named '{}'", wall_name_));
  }
  // Walls that turn about an axis (a polyline's and a mesh's through their axis
  // point): their tangential force is read along the turn, so that a mesh or a
  // polyline drawn in place of a cylinder reads as the cylinder does.
  static bool signed_tangential(const Wall<D>& w) {
    return w.type == WallType::cylinder || (D == 2 && w.type == WallType::polyline) ||
           (D == 3 && w.type == WallType::mesh);
  }
  // Unit tangent of a cylinder's positive rotation at the contact point.
  static V rotation_sense(const Wall<D>& w, const ContactLog<D>& log, std::size_t s) {
    V d = w.radial(log.point[s]);
    const double len = d.norm();
    if (!(len > 0)) return V::Zero();
    d /= len;
    if constexpr (D == 2) {
      return V(-d.y(), d.x());
    } else {
      return w.axis.cross(d);
    }
  }
  void add(double normal, double tangential, const V& total) {
    window_normal_ += normal;
    window_tangential_ += tangential;
    window_total_ += total;
    ++window_samples_;
    sum_normal_ += normal;
    sum_tangential_ += tangential;
    ++total_samples_;
    sum_total_ += total;
    ++vector_samples_;
  }
  void close_window(double time) override {
    if (sink_ && window_samples_ > 0) {
      const double n = window_samples_;
      const V mean = window_total_ / n;
      sink_->append_series(group_, {time, window_normal_ / n, window_tangential_ / n, mean[0],
                                    mean[1], D == 3 ? mean[D - 1] : 0.0, n});
    }
    window_normal_ = window_tangential_ = 0;
    window_total_.setZero();
    window_samples_ = 0;
  }

  std::string wall_name_, label_, group_;
  int wall_ = -1;
  OutputSink* sink_ = nullptr;
  double window_normal_ = 0, window_tangential_ = 0;
  V window_total_ = V::Zero();
  std::int64_t window_samples_ = 0;
  double sum_normal_ = 0, sum_tangential_ = 0;
  std::int64_t total_samples_ = 0;
  V sum_total_ = V::Zero();  // the force vector on the wall, summed over samples
  std::int64_t vector_samples_ = 0;
};

}  // namespace granule
