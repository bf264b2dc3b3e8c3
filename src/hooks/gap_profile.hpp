// The flow across the gap between the chamber wall and the inner piece, the
// premise of dissertation chapter 5: a simple shear flow whose shear rate is
// omega R / H (Eq. 5.6) and whose granular temperature follows from it
// (Eq. 5.4, T^1/2 = sqrt(J / 15 (1 - e)) d du/dy).
//
// Within a sector of +-`sector` degrees about the inner piece (seen from the
// chamber axis), every moving particle whose centre lies between the inner
// piece and the chamber wall is placed at xi = (R - rho) / h(theta): rho its
// distance from the axis, h(theta) the local gap along the ray from the axis
// (xi = 0 at the chamber wall, 1 at the inner piece). Per bin of xi, pooled
// over every sample since attaching: the mean radial and azimuthal velocity
// (about the chamber axis), the granular temperature (the variance of the
// velocity about the bin's mean, per component: <|v - u|^2> / D, the
// azimuthal part taken about the bin's own linear profile), the solid
// fraction (particle volume over the bin's volume, the depth the mean diameter in
// 2D as in the zones diagnostic, 4.3.2) and the count. The shear rate is the
// least-squares slope of the azimuthal velocity against the distance from
// the chamber wall, R - rho, over every particle sample in the sector
// (positive when the powder slows from the wall to the inner piece, for a
// chamber turning counter-clockwise). Beside it: omega R / H with H the
// narrowest gap, and the mean force per particle-particle contact whose
// contact point lies in the sector, the quantity of Eq. 5.10.
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
class GapProfileDiagnostic final : public Diagnostic<D> {
 public:
  using V = Vec<D>;
  static constexpr const char* name = "gap_profile";
  static constexpr const char* doc =
      "flow across the inner piece's gap (Eqs. 5.4, 5.6): per bin of the normalised distance "
      "from the chamber wall, mean radial and azimuthal velocity, granular temperature, solid "
      "fraction; the shear rate beside omega R / H; force per particle-particle contact in "
      "the sector";
  static OptionDocs options() {
    OptionDocs o = ChamberFrame<D>::option_docs(true);
    o.insert(o.end(),
             {{"sector", "deg", "10", "half-width of the sector about the inner piece, in (0, 90]"},
              {"bins", "-", "8", "bins across the gap (at most 1000)"},
              {"depth", "m", "0",
               "the slab's length in 3D (required there); 0 in 2D: the moving "
               "particles' mean diameter"},
              {"label", "", "gap_profile", "group under /diagnostics"}});
    Sampling::add_option_docs(o, {10, 0.01});
    return o;
  }

  explicit GapProfileDiagnostic(DiagnosticOptions& o) : Diagnostic<D>(name) {
    frame_.read(o, true);
    sector_deg_ = o.number_in("sector", 10, 0, 90, "deg");
    if (!(sector_deg_ > 0))
      throw InputError(fmt::format("{}: sector must be > 0 [deg]", o.context()));
    bins_ = static_cast<int>(o.integer("bins", 8, 1, 1000));
    depth_ = o.number_in("depth", 0, 0, 1e9, "m");
    this->sampling_.read(o, {10, 0.01});
    label_ = o.string("label", "gap_profile");
    total_.resize(bins_);
    in_window_.resize(bins_);
  }

  typename Diagnostic<D>::Needs needs() const override { return {true, false}; }

  void attach_output(OutputSink* sink) override {
    sink_ = sink;
    declared_ = false;
  }

  void sample(const StepView<D>& v) override {
    resolve(v);
    declare();
    const auto& p = v.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.fixed[i]) continue;
      double xi = 0, y = 0, ur = 0, ut = 0;
      if (!place(p.position[i], xi, y)) continue;
      polar_velocity(p.position[i], p.velocity[i], ur, ut);
      const double uz = D == 3 ? p.velocity[i][D - 1] : 0.0;
      const int k = std::min(bins_ - 1, static_cast<int>(xi * bins_));
      const double volume = 4.0 / 3.0 * pi * std::pow(p.radius[i], 3);
      for (auto* acc : {&total_, &in_window_}) {
        acc->bins[k].add(ur, ut, uz, volume, y);
        acc->fit.add(y, ut);
      }
    }
    const auto& log = v.contacts;
    for (std::size_t s = 0; s < log.size(); ++s) {
      if (!log.active[s] || ContactLog<D>::is_wall(log.b[s])) continue;
      if (p.fixed[log.a[s]] || p.fixed[log.b[s]]) continue;
      double xi = 0, y = 0;
      if (!place(log.point[s], xi, y)) continue;
      for (auto* acc : {&total_, &in_window_})
        acc->contact_normal += std::abs(log.normal_force[s]),
            acc->contact_tangential += log.tangential[s].norm(), acc->contacts += 1;
    }
    ++total_.samples, ++in_window_.samples;
  }

  std::map<std::string, double> results() const override {
    std::map<std::string, double> r = summary(total_);
    r["sector_deg"] = sector_deg_;
    r["narrowest_gap"] = narrowest_gap_;
    r["mean_gap"] = mean_gap_;
    r["samples"] = static_cast<double>(total_.samples);
    return r;
  }

  std::map<std::string, std::vector<double>> arrays() const override {
    std::map<std::string, std::vector<double>> a;
    std::vector<double> edges(bins_ + 1);
    for (int k = 0; k <= bins_; ++k) edges[k] = static_cast<double>(k) / bins_;
    a["xi_edges"] = edges;
    a["bin_volume"] = bin_volume_;
    const auto profile = profiles(total_);
    for (int q = 0; q < profile_count; ++q) a[profile_names[q]] = profile[q];
    return a;
  }

  const std::string& label() const override { return label_; }
  std::string describe() const override {
    return fmt::format("gap profile +-{} deg about '{}', {} bins, {}", sector_deg_,
                       frame_.inner_name, bins_, this->sampling_.describe());
  }

  void save_own(DiagnosticStateWriter& w) const override {
    frame_.save(w);
    w.put_integers("counts", {total_.samples, in_window_.samples});
    w.put("diameter", diameter_);
    w.put("total", flat(total_));
    w.put("window_sums", flat(in_window_));
  }
  void load_own(const DiagnosticStateReader& r) override {
    const auto counts = r.integers("counts", 2);
    if (counts[0] < 0 || counts[1] < 0 || counts[1] > counts[0])
      r.invalid("counts", "holds impossible counts");
    GapProfileDiagnostic next = *this;
    next.frame_.load(r);
    next.geometry_ready_ = false;
    next.diameter_ = r.number("diameter");
    unflat(r.doubles("total", flat_size()), next.total_);
    unflat(r.doubles("window_sums", flat_size()), next.in_window_);
    next.total_.samples = counts[0], next.in_window_.samples = counts[1];
    *this = std::move(next);
  }

 private:
  enum Profile {
    radial_velocity,
    azimuthal_velocity,
    temperature,
    solid_fraction,
    count,
    profile_count
  };
  static constexpr std::array<const char*, profile_count> profile_names = {
      "radial_velocity", "azimuthal_velocity", "granular_temperature", "solid_fraction", "count"};

  struct Bin {
    double n = 0, ur = 0, ut = 0, uz = 0, ur2 = 0, ut2 = 0, uz2 = 0, volume = 0;
    double y = 0, yy = 0, yut = 0;  // for the shear within the bin
    void add(double r, double t, double z, double vol, double yv) {
      n += 1, ur += r, ut += t, uz += z, ur2 += r * r, ut2 += t * t, uz2 += z * z, volume += vol;
      y += yv, yy += yv * yv, yut += yv * t;
    }
  };
  struct Fit {  // least squares of u against y
    double n = 0, y = 0, yy = 0, u = 0, yu = 0;
    void add(double yv, double uv) { n += 1, y += yv, yy += yv * yv, u += uv, yu += yv * uv; }
    double slope() const {
      const double den = n * yy - y * y;
      return n > 1 && den > 0 ? (n * yu - y * u) / den : 0;
    }
  };
  struct Accumulator {
    std::vector<Bin> bins;
    Fit fit;
    double contact_normal = 0, contact_tangential = 0, contacts = 0;
    std::int64_t samples = 0;
    void resize(int b) { bins.assign(b, Bin{}); }
  };

  // The inner piece's centre and radius, the narrowest gap and the bins' volumes.
  void resolve(const StepView<D>& v) {
    frame_.resolve(v.walls, name);
    if (geometry_ready_) return;
    const Wall<D>* inner = nullptr;
    for (const auto& w : v.walls)
      if (w.name == frame_.inner_name) inner = &w;
    if (!inner)
      throw InputError(fmt::format("diagnostic '{}': no wall named '{}'", name, frame_.inner_name));
    if (inner->type != WallType::cylinder)
      throw InputError(fmt::format(
          "diagnostic '{}': the inner piece '{}' must be a cylinder (the gap's bins are cut "
          "between two circles)",
          name, frame_.inner_name));
    inner_radius_ = inner->radius;
    const double dx = inner->center.x() - frame_.center.x(),
                 dy = inner->center.y() - frame_.center.y();
    offset_ = std::sqrt(dx * dx + dy * dy);
    narrowest_gap_ = frame_.radius - offset_ - inner_radius_;
    if (!(narrowest_gap_ > 0))
      throw InputError(
          fmt::format("diagnostic '{}': the inner piece '{}' does not lie inside the "
                      "chamber '{}' (narrowest gap {} m)",
                      name, frame_.inner_name, frame_.chamber_name, narrowest_gap_));
    // Every ray of the sector must meet the inner piece: offset sin(sector) < r_i.
    if (offset_ * std::sin(sector_deg_ * pi / 180) >= inner_radius_)
      throw InputError(fmt::format(
          "diagnostic '{}': sector {} deg is wider than the inner piece seen from the axis "
          "(at most {:.4g} deg for an inner piece of radius {} m at {} m from it)",
          name, sector_deg_, std::asin(std::min(1.0, inner_radius_ / offset_)) * 180 / pi,
          inner_radius_, offset_));
    // The moving particles' mean diameter at the first sample, as zones takes
    // it (4.3.2): the depth in 2D when none is given. Saved, so that a restart
    // keeps it.
    if (diameter_ == 0) {
      double sum = 0;
      int n = 0;
      for (std::size_t i = 0; i < v.particles.size(); ++i)
        if (!v.particles.fixed[i]) sum += 2 * v.particles.radius[i], ++n;
      if (n == 0 && D == 2 && !(depth_ > 0))
        throw InputError(fmt::format(
            "diagnostic '{}': no moving particles to set the depth (their mean diameter in 2D); "
            "give 'depth' (m)",
            name));
      diameter_ = n > 0 ? sum / n : 0.0;
    }
    const double depth = depth_ > 0 ? depth_ : (D == 2 ? diameter_ : 0.0);
    if (!(depth > 0))
      throw InputError(
          fmt::format("diagnostic '{}': give 'depth' (m), the slab's length in 3D", name));
    // Bin volumes by the midpoint rule over the sector (the local gap is smooth).
    bin_volume_.assign(bins_, 0.0);
    const int steps = 4000;
    const double width = 2 * sector_deg_ * pi / 180, dtheta = width / steps;
    mean_gap_ = 0;
    for (int s = 0; s < steps; ++s) {
      const double h = local_gap(-0.5 * width + (s + 0.5) * dtheta);
      mean_gap_ += h / steps;
      for (int k = 0; k < bins_; ++k) {
        const double outer = frame_.radius - h * k / bins_,
                     in = frame_.radius - h * (k + 1) / bins_;
        bin_volume_[k] += 0.5 * (outer * outer - in * in) * dtheta * depth;
      }
    }
    geometry_ready_ = true;
  }

  // Distance from the axis to the inner piece's far surface along the ray at
  // angle theta from the inner piece's direction, and the gap left to the wall.
  double local_gap(double theta) const {
    const double s = offset_ * std::sin(theta);
    return frame_.radius -
           (offset_ * std::cos(theta) + std::sqrt(inner_radius_ * inner_radius_ - s * s));
  }
  // xi and the distance from the wall of a point in the sector's gap; false outside.
  bool place(const V& x, double& xi, double& y) const {
    double angle = frame_.angle_deg(x);
    if (angle > 180) angle -= 360;
    if (std::abs(angle) > sector_deg_) return false;
    const double h = local_gap(angle * pi / 180);
    y = frame_.radius - frame_.radial_distance(x);
    xi = y / h;
    if (xi > 1) return false;  // between the axis and the inner piece, or inside it
    xi = std::max(0.0, xi);    // a centre pressed past the wall
    return true;
  }
  void polar_velocity(const V& x, const V& u, double& ur, double& ut) const {
    const double dx = x.x() - frame_.center.x(), dy = x.y() - frame_.center.y();
    const double l = std::sqrt(dx * dx + dy * dy);
    if (l == 0) return;
    ur = (u.x() * dx + u.y() * dy) / l;
    ut = (u.y() * dx - u.x() * dy) / l;
  }

  std::array<std::vector<double>, profile_count> profiles(const Accumulator& acc) const {
    std::array<std::vector<double>, profile_count> out;
    for (auto& q : out) q.assign(bins_, 0.0);
    const double samples = static_cast<double>(acc.samples);
    for (int k = 0; k < bins_; ++k) {
      const Bin& b = acc.bins[k];
      if (samples > 0 && k < static_cast<int>(bin_volume_.size()) && bin_volume_[k] > 0)
        out[solid_fraction][k] = b.volume / samples / bin_volume_[k];
      out[count][k] = samples > 0 ? b.n / samples : 0;
      if (b.n == 0) continue;
      const double mr = b.ur / b.n, mt = b.ut / b.n, mz = b.uz / b.n;
      out[radial_velocity][k] = mr;
      out[azimuthal_velocity][k] = mt;
      // The azimuthal variance about the bin's own linear profile: the mean
      // shear across a bin's width is flow, not temperature.
      const double my = b.y / b.n, var_y = b.yy / b.n - my * my;
      const double cov = b.yut / b.n - my * mt;
      double var_t = b.ut2 / b.n - mt * mt;
      if (var_y > 0) var_t -= cov * cov / var_y;
      const double var = (b.ur2 / b.n - mr * mr) + var_t + (b.uz2 / b.n - mz * mz);
      out[temperature][k] = std::max(0.0, var) / D;
    }
    return out;
  }

  std::map<std::string, double> summary(const Accumulator& acc) const {
    std::map<std::string, double> r;
    const double sign = frame_.omega >= 0 ? 1 : -1;
    r["shear_rate"] = -sign * acc.fit.slope();
    r["nominal_shear_rate"] =  // 0 before the first sample has found the gap
        narrowest_gap_ > 0 ? std::abs(frame_.omega) * frame_.radius / narrowest_gap_ : 0.0;
    r["wall_speed"] = std::abs(frame_.omega) * frame_.radius;
    // Sector means: temperature weighted by count, solid fraction over the whole sector.
    double n = 0, t = 0, volume = 0, sector_volume = 0;
    const auto profile = profiles(acc);
    for (int k = 0; k < bins_; ++k) {
      n += acc.bins[k].n, t += acc.bins[k].n * profile[temperature][k];
      volume += acc.bins[k].volume;
      if (k < static_cast<int>(bin_volume_.size())) sector_volume += bin_volume_[k];
    }
    r["mean_granular_temperature"] = n > 0 ? t / n : 0;
    const double samples = static_cast<double>(acc.samples);
    r["mean_solid_fraction"] =
        samples > 0 && sector_volume > 0 ? volume / samples / sector_volume : 0;
    r["particles"] = samples > 0 ? n / samples : 0;
    r["diameter"] = diameter_;
    r["contacts"] = samples > 0 ? acc.contacts / samples : 0;
    r["normal_force_per_contact"] = acc.contacts > 0 ? acc.contact_normal / acc.contacts : 0;
    r["tangential_force_per_contact"] =
        acc.contacts > 0 ? acc.contact_tangential / acc.contacts : 0;
    return r;
  }

  std::string fingerprint() const override {
    return fmt::format(
        "{}; chamber {}; inner piece {}; sector {:.17g}; bins {}; depth {:.17g}; "
        "label {}",
        name, frame_.chamber_name, frame_.inner_name, sector_deg_, bins_, depth_, label_);
  }
  std::size_t flat_size() const { return 11 * static_cast<std::size_t>(bins_) + 5 + 3; }
  static std::vector<double> flat(const Accumulator& acc) {
    std::vector<double> out;
    for (const Bin& b : acc.bins)
      out.insert(out.end(),
                 {b.n, b.ur, b.ut, b.uz, b.ur2, b.ut2, b.uz2, b.volume, b.y, b.yy, b.yut});
    out.insert(out.end(), {acc.fit.n, acc.fit.y, acc.fit.yy, acc.fit.u, acc.fit.yu});
    out.insert(out.end(), {acc.contact_normal, acc.contact_tangential, acc.contacts});
    return out;
  }
  void unflat(const std::vector<double>& in, Accumulator& acc) const {
    acc.resize(bins_);
    const double* x = in.data();
    for (Bin& b : acc.bins)
      b = {x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8], x[9], x[10]}, x += 11;
    acc.fit = {x[0], x[1], x[2], x[3], x[4]};
    acc.contact_normal = x[5], acc.contact_tangential = x[6], acc.contacts = x[7];
  }

  void declare() {
    if (declared_ || !sink_) return;
    declared_ = true;
    const std::string g = "diagnostics/" + label_;
    sink_->declare_series(g + "/sector",
                          {"time", "shear_rate", "nominal_shear_rate", "granular_temperature",
                           "solid_fraction", "particles", "normal_force_per_contact"});
    sink_->write_attribute(g + "/sector", "units", std::string("s, 1/s, 1/s, m^2/s^2, -, -, N"));
    std::vector<std::string> columns{"time"};
    for (int k = 1; k <= bins_; ++k) columns.push_back(fmt::format("bin_{}", k));
    // Each profile's bins in one unit (the time column in s).
    static constexpr std::array<const char*, profile_count> profile_units = {"m/s", "m/s",
                                                                             "m^2/s^2", "-", "-"};
    for (int q = 0; q < profile_count; ++q) {
      sink_->declare_series(g + "/" + profile_names[q], columns);
      sink_->write_attribute(g + "/" + profile_names[q], "units", std::string(profile_units[q]));
    }
    this->write_sampling_attributes(*sink_, g);
    sink_->write_attribute(g, "sector_deg", sector_deg_);
    sink_->write_attribute(g, "narrowest_gap", narrowest_gap_);
    sink_->write_attribute(g, "bin_volume", bin_volume_);
    sink_->write_attribute(
        g, "bins", std::string("xi = (R - rho) / h(theta) in equal bins, 0 at the chamber wall"));
  }

  void close_window(double time) override {
    if (sink_ && in_window_.samples > 0) {
      declare();
      const std::string g = "diagnostics/" + label_;
      const auto s = summary(in_window_);
      sink_->append_series(
          g + "/sector",
          {time, s.at("shear_rate"), s.at("nominal_shear_rate"), s.at("mean_granular_temperature"),
           s.at("mean_solid_fraction"), s.at("particles"), s.at("normal_force_per_contact")});
      const auto profile = profiles(in_window_);
      for (int q = 0; q < profile_count; ++q) {
        std::vector<double> row{time};
        row.insert(row.end(), profile[q].begin(), profile[q].end());
        sink_->append_series(g + "/" + profile_names[q], row);
      }
    }
    in_window_ = Accumulator{};
    in_window_.resize(bins_);
  }

  ChamberFrame<D> frame_;
  double sector_deg_ = 10, depth_ = 0;
  int bins_ = 8;
  std::string label_;
  OutputSink* sink_ = nullptr;
  bool declared_ = false, geometry_ready_ = false;
  double inner_radius_ = 0, offset_ = 0, narrowest_gap_ = 0, mean_gap_ = 0, diameter_ = 0;
  std::vector<double> bin_volume_;
  Accumulator total_, in_window_;
};

}  // namespace granule
