// The four areas of dissertation 4.4.2 (inner piece, scraper, input, free
// diffusion), angular sectors about the chamber axis counted from the inner
// piece (chamber_frame.hpp). Per area and time window:
//   mean normal and tangential contact force per particle (Figs. 4.20-4.21):
//     the sum of |N| (|T|) over a particle's contacts, averaged over the
//     particles whose centres are in the area;
//   mean normal and tangential force per particle-particle contact (the
//     "average inter-particle force" of Figs. 4.32, 4.34, 5.9-5.13);
//   mean number of particles;
//   cumulative collisions particle-particle and particle-boundary (walls and
//     fixed particles), counted when a contact begins, in the area of its
//     first contact point (Figs. 4.22-4.23); contacts going on when event
//     tracking starts (a diagnostic attached to a settled bed) are not counted;
//   collision ratio = cumulative collisions / mean number of particles in the
//     area (Eq. 4.14; Figs. 4.24-4.25).
#pragma once

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "hooks/chamber_frame.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

template <int D>
class AreasDiagnostic final : public Diagnostic<D> {
 public:
  using V = Vec<D>;
  static constexpr int A = AreaSectors::count;
  static constexpr const char* name = "areas";
  static constexpr const char* doc =
      "the four areas of 4.4.2 as sectors (deg from the inner piece): mean normal/tangential "
      "force per particle and per particle-particle contact, cumulative collisions and "
      "collision ratio (4.14)";
  static OptionDocs options() {
    OptionDocs o = ChamberFrame<D>::option_docs(true);
    for (const auto& a : AreaSectors::option_docs()) o.push_back(a);
    o.push_back({"label", "", "areas", "group under /diagnostics"});
    Sampling::add_option_docs(o, {10, 0.01});
    return o;
  }

  enum Series {
    normal_per_particle,
    tangential_per_particle,
    normal_per_contact,
    tangential_per_contact,
    particles,
    collisions_particle,
    collisions_boundary,
    collision_ratio_particle,
    collision_ratio_boundary,
    series_count
  };
  static constexpr const char* series_names[series_count] = {"normal_force_per_particle",
                                                             "tangential_force_per_particle",
                                                             "normal_force_per_contact",
                                                             "tangential_force_per_contact",
                                                             "particles",
                                                             "collisions_particle",
                                                             "collisions_boundary",
                                                             "collision_ratio_particle",
                                                             "collision_ratio_boundary"};
  static constexpr const char* series_units[series_count] = {"N", "N", "N", "N", "-",
                                                             "-", "-", "-", "-"};

  explicit AreasDiagnostic(DiagnosticOptions& o) : Diagnostic<D>(name) {
    frame_.read(o, true);
    sectors_.read(o);
    this->sampling_.read(o, {10, 0.01});
    label_ = o.string("label", "areas");
  }

  typename Diagnostic<D>::Needs needs() const override { return {true, true}; }

  void attach_output(OutputSink* sink) override {
    sink_ = sink;
    declared_ = false;
  }

  // Collisions: every step, from the contacts that began.
  void on_events(const StepView<D>& v) override {
    frame_.resolve(v.walls, name);
    const auto& p = v.particles;
    for (const auto& e : v.contacts.began) {
      const int area = sectors_.area_of(frame_.angle_deg(e.position));
      if (area < 0) continue;
      bool boundary = e.id_b < 0;
      if (!boundary) {
        const int ia = p.index(e.id_a), ib = p.index(e.id_b);
        boundary = (ia >= 0 && p.fixed[ia]) || (ib >= 0 && p.fixed[ib]);
      }
      ++(boundary ? boundary_collisions_ : particle_collisions_)[area];
    }
  }

  void sample(const StepView<D>& v) override {
    frame_.resolve(v.walls, name);
    declare();
    const auto& p = v.particles;
    const auto& log = v.contacts;
    normal_.assign(p.size(), 0.0);
    tangential_.assign(p.size(), 0.0);
    std::array<double, A> contact_normal{}, contact_tangential{}, contacts{};
    for (std::size_t s = 0; s < log.size(); ++s) {
      if (!log.active[s]) continue;
      const double n = std::abs(log.normal_force[s]), t = log.tangential[s].norm();
      const int a = log.a[s];
      normal_[a] += n, tangential_[a] += t;
      if (ContactLog<D>::is_wall(log.b[s])) continue;
      const int b = log.b[s];
      normal_[b] += n, tangential_[b] += t;
      if (p.fixed[a] || p.fixed[b]) continue;
      const int area = sectors_.area_of(frame_.angle_deg(log.point[s]));
      if (area < 0) continue;
      contact_normal[area] += n, contact_tangential[area] += t, contacts[area] += 1;
    }
    std::array<double, A> count{}, particle_normal{}, particle_tangential{};
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.fixed[i]) continue;
      const int area = sectors_.area_of(frame_.angle_deg(p.position[i]));
      if (area < 0) continue;
      count[area] += 1;
      particle_normal[area] += normal_[i];
      particle_tangential[area] += tangential_[i];
    }
    for (int k = 0; k < A; ++k) {
      window_.sums[k].add(count[k], particle_normal[k], particle_tangential[k], contacts[k],
                          contact_normal[k], contact_tangential[k]);
      total_.sums[k].add(count[k], particle_normal[k], particle_tangential[k], contacts[k],
                         contact_normal[k], contact_tangential[k]);
    }
    ++window_.samples;
    ++total_.samples;
  }

  std::map<std::string, double> results() const override {
    std::map<std::string, double> r;
    const auto values = row_values(total_);
    for (int q = 0; q < series_count; ++q)
      for (int k = 0; k < A; ++k)
        r[std::string(series_names[q]) + "_" + AreaSectors::names[k]] = values[q][k];
    r["samples"] = static_cast<double>(total_.samples);
    return r;
  }

  const std::string& label() const override { return label_; }
  std::string describe() const override {
    return fmt::format("4 areas about '{}' from '{}' {}", frame_.chamber_name, frame_.inner_name,
                       this->sampling_.describe());
  }

  // The per-particle force buffers are refilled by every observe(): not state.
  void save_own(DiagnosticStateWriter& w) const override {
    frame_.save(w);
    w.put_integers("counts", {window_.samples, total_.samples});
    w.put("window_sums", flat(window_));
    w.put("total_sums", flat(total_));
    w.put_integers("collisions_particle", particle_collisions_);
    w.put_integers("collisions_boundary", boundary_collisions_);
  }
  void load_own(const DiagnosticStateReader& r) override {
    const auto counts = r.integers("counts", 2);
    if (counts[0] < 0 || counts[1] < counts[0]) r.invalid("counts", "holds impossible counts");
    AreasDiagnostic next = *this;  // all or nothing: a refused load leaves this as it was
    next.frame_.load(r);
    unflat(r.doubles("window_sums", 6 * A), next.window_);
    unflat(r.doubles("total_sums", 6 * A), next.total_);
    next.window_.samples = counts[0], next.total_.samples = counts[1];
    r.read("collisions_particle", next.particle_collisions_);
    r.read("collisions_boundary", next.boundary_collisions_);
    *this = std::move(next);
  }

 private:
  struct Sums {
    double particles = 0, particle_normal = 0, particle_tangential = 0;
    double contacts = 0, contact_normal = 0, contact_tangential = 0;
    void add(double c, double pn, double pt, double nc, double cn, double ct) {
      particles += c, particle_normal += pn, particle_tangential += pt;
      contacts += nc, contact_normal += cn, contact_tangential += ct;
    }
  };
  struct Accumulator {
    std::array<Sums, A> sums{};
    std::int64_t samples = 0;
  };
  std::string fingerprint() const override {
    return fmt::format("{}; chamber {}; inner piece {}; sectors {:.17g}; label {}", name,
                       frame_.chamber_name, frame_.inner_name, fmt::join(sectors_.bounds(), " "),
                       label_);
  }
  static std::vector<double> flat(const Accumulator& acc) {
    std::vector<double> out;
    for (const Sums& s : acc.sums)
      out.insert(out.end(), {s.particles, s.particle_normal, s.particle_tangential, s.contacts,
                             s.contact_normal, s.contact_tangential});
    return out;
  }
  static void unflat(const std::vector<double>& in, Accumulator& acc) {
    for (int k = 0; k < A; ++k) {
      const double* x = &in[6 * k];
      acc.sums[k] = {x[0], x[1], x[2], x[3], x[4], x[5]};
    }
  }

  // One value per series and area from an accumulator (collisions are cumulative).
  std::array<std::array<double, A>, series_count> row_values(const Accumulator& acc) const {
    std::array<std::array<double, A>, series_count> out{};
    for (int k = 0; k < A; ++k) {
      const Sums& s = acc.sums[k];
      auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
      out[normal_per_particle][k] = ratio(s.particle_normal, s.particles);
      out[tangential_per_particle][k] = ratio(s.particle_tangential, s.particles);
      out[normal_per_contact][k] = ratio(s.contact_normal, s.contacts);
      out[tangential_per_contact][k] = ratio(s.contact_tangential, s.contacts);
      out[particles][k] = ratio(s.particles, static_cast<double>(acc.samples));
      out[collisions_particle][k] = static_cast<double>(particle_collisions_[k]);
      out[collisions_boundary][k] = static_cast<double>(boundary_collisions_[k]);
      // Eq. 4.14 over the whole time since attaching: the mean count is the long-time one.
      const double mean_count =
          ratio(total_.sums[k].particles, static_cast<double>(total_.samples));
      out[collision_ratio_particle][k] = ratio(particle_collisions_[k], mean_count);
      out[collision_ratio_boundary][k] = ratio(boundary_collisions_[k], mean_count);
    }
    return out;
  }

  void declare() {
    if (declared_ || !sink_) return;
    declared_ = true;
    for (int q = 0; q < series_count; ++q) {
      sink_->declare_series(group(q), area_columns());
      sink_->write_attribute(group(q), "units", std::string(series_units[q]));
    }
    const std::string g = "diagnostics/" + label_;
    this->write_sampling_attributes(*sink_, g);
    sink_->write_attribute(g, "area_bounds_deg", sectors_.bounds());
    sink_->write_attribute(g, "chamber", frame_.chamber_name);
    sink_->write_attribute(g, "inner_piece", frame_.inner_name);
  }
  std::string group(int q) const { return "diagnostics/" + label_ + "/" + series_names[q]; }

  void close_window(double time) override {
    if (sink_ && window_.samples > 0) {
      declare();
      const auto values = row_values(window_);
      for (int q = 0; q < series_count; ++q) {
        std::vector<double> row{time};
        row.insert(row.end(), values[q].begin(), values[q].end());
        sink_->append_series(group(q), row);
      }
    }
    window_ = Accumulator{};
  }

  ChamberFrame<D> frame_;
  AreaSectors sectors_;
  std::string label_;
  OutputSink* sink_ = nullptr;
  bool declared_ = false;
  std::vector<double> normal_, tangential_;  // per particle, this sample
  Accumulator window_, total_;
  std::array<std::int64_t, A> particle_collisions_{}, boundary_collisions_{};
};

}  // namespace granule
