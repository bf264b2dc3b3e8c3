// The deepest contacts of a run: the largest overlap as a fraction of the
// moving particle's radius (of the smaller radius for two moving particles),
// kept apart for particle-particle, particle-fixed-particle and particle-wall
// contacts, with where and when the deepest one was. A soft-sphere model is
// trusted only while overlaps stay small: the dissertation's Walton-Braun
// runs show deformations below 1 % of a diameter (5.4.2), and a particle
// jammed in a wedge shows up here as a ratio of tens of per cent that holds
// for the whole run.
//
// Every contact that ends reports the largest overlap it reached (the
// engine tracks it every step), so the peak of each collision is exact
// whatever `every` is; contacts still going on (a jammed particle's) are read
// from the contact log every `every` steps.
#pragma once

#include <fmt/format.h>

#include <array>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

template <int D>
class OverlapsDiagnostic final : public Diagnostic<D> {
 public:
  using V = Vec<D>;
  static constexpr const char* name = "overlaps";
  static constexpr const char* doc =
      "largest overlap / radius of particle-particle, particle-fixed-particle and particle-wall "
      "contacts, per window and since attaching, with the deepest contact's time (the sample "
      "that saw it, or its end where only its end saw the peak), place and particle";
  static OptionDocs options() {
    OptionDocs o{{"label", "", "overlaps", "group under /diagnostics"}};
    Sampling::add_option_docs(o, {10, 0.01, "window of the series' maxima"});
    return o;
  }
  enum Kind { particle, fixed, wall, kinds };
  static constexpr std::array<const char*, kinds> kind_names = {"particle", "fixed", "wall"};

  explicit OverlapsDiagnostic(DiagnosticOptions& o) : Diagnostic<D>(name) {
    this->sampling_.read(o, {10, 0.01, "window of the series' maxima"});
    label_ = o.string("label", "overlaps");
  }

  typename Diagnostic<D>::Needs needs() const override { return {true, true}; }

  void attach_output(OutputSink* sink) override {
    sink_ = sink;
    declared_ = false;
  }

  // Contacts that ended this step, with the peak each reached.
  void on_events(const StepView<D>& v) override {
    const auto& p = v.particles;
    for (const auto& e : v.contacts.ended) {
      const int a = p.index(e.id_a), b = e.id_b < 0 ? -1 : p.index(e.id_b);
      if (a < 0 || (e.id_b >= 0 && b < 0)) continue;  // a particle removed meanwhile
      note(p, a, e.id_b < 0 ? -1 : b, e.peak_overlap, e.end_time, e.position);
    }
  }

  // Contacts going on now, from the log.
  void sample(const StepView<D>& v) override {
    declare();
    const auto& p = v.particles;
    const auto& log = v.contacts;
    for (std::size_t s = 0; s < log.size(); ++s) {
      if (!log.active[s]) continue;
      note(p, log.a[s], ContactLog<D>::is_wall(log.b[s]) ? -1 : log.b[s], log.overlap[s], v.time,
           log.point[s]);
    }
    ++samples_;
  }

  std::map<std::string, double> results() const override {
    std::map<std::string, double> r;
    double all = 0;
    for (int k = 0; k < kinds; ++k) {
      r[std::string("max_overlap_ratio_") + kind_names[k]] = deepest_[k];
      if (deepest_[k] > all) all = deepest_[k];
    }
    r["max_overlap_ratio"] = all;
    r["samples"] = static_cast<double>(samples_);
    if (worst_kind_ >= 0) {
      r["deepest_time"] = worst_time_;
      r["deepest_kind"] = worst_kind_;  // 0 particle, 1 fixed particle, 2 wall
      r["deepest_particle"] = static_cast<double>(worst_id_);
      for (int k = 0; k < D; ++k) r[std::string("deepest_") + "xyz"[k]] = worst_point_[k];
    }
    return r;
  }

  const std::string& label() const override { return label_; }
  std::string describe() const override {
    return fmt::format("deepest overlaps {}", this->sampling_.describe());
  }

  void save_own(DiagnosticStateWriter& w) const override {
    w.put_integers("counts", {samples_, worst_kind_, worst_id_});
    w.put("times", {worst_time_, worst_ratio_});
    w.put("deepest", deepest_);
    w.put("in_window", in_window_);
    w.put("deepest_point", std::vector<double>(worst_point_.data(), worst_point_.data() + D));
  }
  void load_own(const DiagnosticStateReader& r) override {
    const auto counts = r.integers("counts", 3);
    if (counts[0] < 0 || counts[1] < -1 || counts[1] >= kinds)
      r.invalid("counts", "holds impossible counts");
    OverlapsDiagnostic next = *this;
    next.samples_ = counts[0], next.worst_kind_ = static_cast<int>(counts[1]);
    next.worst_id_ = counts[2];
    const auto times = r.doubles("times", 2);
    next.worst_time_ = times[0], next.worst_ratio_ = times[1];
    r.read("deepest", next.deepest_);
    r.read("in_window", next.in_window_);
    const auto point = r.doubles("deepest_point", D);
    for (int k = 0; k < D; ++k) next.worst_point_[k] = point[k];
    *this = std::move(next);
  }

 private:
  std::string fingerprint() const override { return fmt::format("{}; label {}", name, label_); }
  // One contact of particle a with particle b (-1: a wall) at `overlap`.
  void note(const Particles<D>& p, int a, int b, double overlap, double time, const V& point) {
    Kind kind = wall;
    double radius = p.radius[a];
    int deep = a;  // the moving particle the ratio refers to
    if (b >= 0) {
      if (p.fixed[a] || p.fixed[b]) {
        kind = fixed;
        deep = p.fixed[a] ? b : a;
        radius = p.radius[deep];
      } else {
        kind = particle;
        if (p.radius[b] < radius) radius = p.radius[b], deep = b;
      }
    }
    const double ratio = overlap / radius;
    if (ratio > in_window_[kind]) in_window_[kind] = ratio;
    if (ratio > deepest_[kind]) {
      deepest_[kind] = ratio;
      if (ratio > worst_ratio_) {
        worst_ratio_ = ratio, worst_time_ = time, worst_kind_ = kind;
        worst_id_ = p.id[deep];
        worst_point_ = point;
      }
    }
  }

  void declare() {
    if (declared_ || !sink_) return;
    declared_ = true;
    const std::string g = "diagnostics/" + label_;
    sink_->declare_series(g + "/max_overlap_ratio", {"time", "particle", "fixed", "wall"});
    sink_->write_attribute(g + "/max_overlap_ratio", "units", std::string("s, -, -, -"));
    sink_->write_attribute(g + "/max_overlap_ratio", "quantity",
                           std::string("overlap / radius, largest in the window"));
    this->write_sampling_attributes(*sink_, g);
  }

  void close_window(double time) override {
    if (sink_)
      sink_->append_series("diagnostics/" + label_ + "/max_overlap_ratio",
                           {time, in_window_[particle], in_window_[fixed], in_window_[wall]});
    in_window_ = {};
  }

  std::string label_;
  OutputSink* sink_ = nullptr;
  bool declared_ = false;
  std::array<double, kinds> deepest_{}, in_window_{};
  double worst_ratio_ = 0, worst_time_ = 0;
  int worst_kind_ = -1;
  std::int64_t worst_id_ = -1, samples_ = 0;
  V worst_point_ = V::Zero();
};

}  // namespace granule
