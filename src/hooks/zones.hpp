// Radial zones of equal volume over the chamber (dissertation 4.2.3, 4.3.2):
// N zones with boundaries r_k = R sqrt(k/N); a particle cut by a boundary is
// shared between the two zones by the spherical-cap volume fractions of
// Eqs. 4.3-4.6. Per zone, averaged over time windows:
//   rotational kinetic energy with the chamber spin removed (4.10),
//   deviatoric kinetic energy (4.11): fluctuations about the zone's mean
//     velocity taken in polar components (SPEC 4.2: the Cartesian mean of a
//     whole annulus is ~0 by symmetry) and, as printed, in Cartesian ones,
//   pressure (4.12): kinetic part plus the virial of the contact forces,
//   collision work (4.13) as a rate: sum of N d(alpha)/dt per unit volume,
//   solid fraction and particle count.
// Zone volume = zone area x depth; in 2D the depth is one particle diameter
// (4.3.2), in 3D the slab's length along the axis. Fixed particles (the
// scraper) are boundary, not powder: their contacts count, they do not.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "hooks/chamber_frame.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

// Fraction of a sphere of radius r, centre at distance l from the axis, that
// lies inside radius b (planar cut, Eqs. 4.3-4.5): a = l - b (4.3); the part
// beyond the plane at distance a from the centre has the cap volume
// (2/3) pi r^3 - pi a (r^2 - a^2/3) (4.4), divided by V_t (4.5).
inline double zone_inner_fraction(double l, double b, double r) {
  const double a = l - b;  // Eq. 4.3
  if (a >= r) return 0;
  if (a <= -r) return 1;
  const double cap = 2.0 / 3.0 * r * r * r - a * (r * r - a * a / 3);  // Eq. 4.4 / pi
  return cap / (4.0 / 3.0 * r * r * r);                                // Eq. 4.5
}

template <int D>
class ZonesDiagnostic final : public Diagnostic<D> {
 public:
  using V = Vec<D>;
  static constexpr const char* name = "zones";
  static constexpr const char* doc =
      "radial zones of equal volume (4.3-4.6): rotational KE less chamber spin (4.10), "
      "deviatoric KE (4.11, polar and Cartesian mean), pressure kinetic + virial (4.12), "
      "collision work rate (4.13), solid fraction";
  static OptionDocs options() {
    OptionDocs o = ChamberFrame<D>::option_docs(false);
    o.insert(o.end(), {{"zones", "-", "7", "number of zones of equal volume (at most 1000)"},
                       {"depth", "m", "0",
                        "zone depth: the slab's length in 3D (required there); 0 in 2D: "
                        "one mean particle diameter (4.3.2)"},
                       {"mean", "", "polar",
                        "'polar' or 'cartesian': the mean velocity the pressure's "
                        "kinetic part (4.12) is taken about"},
                       {"label", "", "zones", "group under /diagnostics"}});
    Sampling::add_option_docs(o, {10, 0.01});
    return o;
  }

  enum Quantity {
    rotational_ke,
    deviatoric_ke,
    deviatoric_ke_cartesian,
    pressure,
    pressure_kinetic,
    pressure_virial,
    collision_work_rate,
    solid_fraction,
    count,
    quantity_count
  };
  static constexpr const char* quantity_names[quantity_count] = {"rotational_ke",
                                                                 "deviatoric_ke",
                                                                 "deviatoric_ke_cartesian",
                                                                 "pressure",
                                                                 "pressure_kinetic",
                                                                 "pressure_virial",
                                                                 "collision_work_rate",
                                                                 "solid_fraction",
                                                                 "count"};
  static constexpr const char* quantity_units[quantity_count] = {
      "J/m^3", "J/m^3", "J/m^3", "Pa", "Pa", "Pa", "W/m^3", "-", "-"};

  explicit ZonesDiagnostic(DiagnosticOptions& o) : Diagnostic<D>(name) {
    frame_.read(o, false);
    zones_ = static_cast<int>(o.integer("zones", 7, 1, 1000));
    depth_ = o.number_in("depth", 0, 0, 1e3, "m");
    depth_option_ = depth_;
    if (D == 3 && !(depth_ > 0))
      throw InputError(fmt::format(
          "{}: give depth = the slab's length along the axis [m] (3D zone volumes)", o.context()));
    const std::string mean = o.string("mean", "polar");
    if (mean != "polar" && mean != "cartesian")
      throw InputError(
          fmt::format("{}: 'mean' must be 'polar' or 'cartesian', got '{}'", o.context(), mean));
    polar_ = mean == "polar";
    this->sampling_.read(o, {10, 0.01});
    label_ = o.string("label", "zones");
  }

  typename Diagnostic<D>::Needs needs() const override { return {true, false}; }

  void attach_output(OutputSink* sink) override {
    sink_ = sink;
    declared_ = false;
  }

  void sample(const StepView<D>& v) override {
    frame_.resolve(v.walls, name);
    const auto& p = v.particles;
    if (volume_.empty()) setup(p);
    declare();
    std::vector<double> sample(quantity_count * zones_, 0.0);
    auto at = [&](Quantity q, int z) -> double& { return sample[q * zones_ + z]; };
    // Per zone sums for the mean velocity: mass, sum m u (polar and Cartesian), sum m u^2.
    std::vector<double> mass(zones_, 0.0), muu(zones_, 0.0);
    std::vector<V> mu_polar(zones_, V::Zero()), mu_cart(zones_, V::Zero());
    std::vector<double> fraction(zones_);
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.fixed[i]) continue;
      const double r = p.radius[i], m = p.mass[i];
      const double inertia = sphere_inertia(m, r);
      const double l = frame_.radial_distance(p.position[i]);
      split(l, r, fraction);
      // Eq. 4.10: spin relative to the chamber's; 2D spin is about z only.
      double spin_sq;
      if constexpr (D == 2) {
        spin_sq = (p.spin[i] - frame_.omega) * (p.spin[i] - frame_.omega);
      } else {
        const auto& w = p.spin[i];
        spin_sq = w.x() * w.x() + w.y() * w.y() + (w.z() - frame_.omega) * (w.z() - frame_.omega);
      }
      const V& vel = p.velocity[i];
      const V local = polar_components(p.position[i], vel);
      const double particle_volume = 4.0 / 3.0 * pi * r * r * r;
      for (int z = 0; z < zones_; ++z) {
        const double f = fraction[z];
        if (f == 0) continue;
        at(rotational_ke, z) += f * inertia * spin_sq;
        at(solid_fraction, z) += f * particle_volume;
        at(count, z) += f;
        mass[z] += f * m;
        mu_polar[z] += f * m * local;
        mu_cart[z] += f * m * vel;
        muu[z] += f * m * vel.squaredNorm();  // |v|^2 is the same in both components
      }
    }
    // Contacts: the virial F_ij R_ij of 4.12 and N d(alpha)/dt of 4.13, each
    // contact in the zone of its contact point. R_ij = r_a + r_b - overlap for
    // a pair (periodic images need no care), r_a - overlap (the particle's
    // side of the contact) for a wall.
    const auto& log = v.contacts;
    for (std::size_t s = 0; s < log.size(); ++s) {
      if (!log.active[s]) continue;
      const int a = log.a[s];
      const int z = zone_of(frame_.radial_distance(log.point[s]));
      double branch = p.radius[a] - log.overlap[s];
      if (!ContactLog<D>::is_wall(log.b[s])) branch += p.radius[log.b[s]];
      at(pressure_virial, z) += log.normal_force[s] * branch;
      // d(alpha)/dt at step n, where N acts: the logged rate is of leap-frog's
      // velocities v(n-1/2), half a step behind, which biases the work by O(dt)
      // (an elastic impact "did" a share of its energy falling as 1/n at n steps
      // per contact, and a particle carried round by the turning chamber, its
      // overlap steady, N omega^2 r dt / 2). Half a step of each particle's
      // acceleration (this step's contact and body forces over m) brings it to
      // step n, as (alpha(n+1) - alpha(n-1)) / 2 dt, whose sum over an elastic
      // impact cancels.
      auto acceleration = [&](int i) -> double {
        if (p.fixed[i]) return 0.0;
        Vec<D> f = p.force_torque[i].force;
        if (v.body) f += v.body->force(p.mass[i], p.position[i]);
        return p.inv_mass[i] * f.dot(log.normal[s]);
      };
      double half_step = -acceleration(a);
      if (!ContactLog<D>::is_wall(log.b[s])) half_step += acceleration(log.b[s]);
      at(collision_work_rate, z) +=
          log.normal_force[s] * (log.overlap_rate[s] + 0.5 * v.dt * half_step);
    }
    for (int z = 0; z < zones_; ++z) {
      const double vk = volume_[z];
      double dev_polar = 0, dev_cart = 0;
      if (mass[z] > 0) {
        dev_polar = std::max(0.0, muu[z] - mu_polar[z].squaredNorm() / mass[z]);
        dev_cart = std::max(0.0, muu[z] - mu_cart[z].squaredNorm() / mass[z]);
      }
      at(rotational_ke, z) /= 2 * vk;                                        // Eq. 4.10
      at(deviatoric_ke, z) = dev_polar / (2 * vk);                           // Eq. 4.11, polar mean
      at(deviatoric_ke_cartesian, z) = dev_cart / (2 * vk);                  // Eq. 4.11 as printed
      at(pressure_kinetic, z) = (polar_ ? dev_polar : dev_cart) / (3 * vk);  // Eq. 4.12
      at(pressure_virial, z) /= 3 * vk;
      at(pressure, z) = at(pressure_kinetic, z) + at(pressure_virial, z);
      at(collision_work_rate, z) /= vk;  // Eq. 4.13 divided by the step
      at(solid_fraction, z) /= vk;
    }
    for (std::size_t k = 0; k < sample.size(); ++k) {
      window_sum_[k] += sample[k];
      total_sum_[k] += sample[k];
    }
    ++window_samples_;
    ++total_samples_;
  }

  std::map<std::string, double> results() const override {
    std::map<std::string, double> r;
    double sum = 0;
    for (double vk : volume_) sum += vk;
    r["zone_volume_sum"] = sum;
    r["chamber_volume"] = pi * frame_.radius * frame_.radius * depth_;
    r["depth"] = depth_;
    r["samples"] = static_cast<double>(total_samples_);
    double particles = 0;
    for (int z = 0; z < zones_ && total_samples_ > 0; ++z)
      particles += total_sum_[count * zones_ + z] / total_samples_;
    r["mean_particle_count"] = particles;
    return r;
  }

  // Long-time means per zone (innermost first), zone radii and volumes.
  std::map<std::string, std::vector<double>> arrays() const override {
    std::map<std::string, std::vector<double>> a;
    for (int q = 0; q < quantity_count; ++q) {
      std::vector<double> m(zones_, 0.0);
      for (int z = 0; z < zones_ && total_samples_ > 0; ++z)
        m[z] = total_sum_[q * zones_ + z] / total_samples_;
      a[quantity_names[q]] = m;
    }
    a["zone_radii"] = radii_;
    a["zone_volume"] = volume_;
    return a;
  }

  const std::string& label() const override { return label_; }
  std::string describe() const override {
    return fmt::format("{} radial zones of '{}' {}, {} mean", zones_, frame_.chamber_name,
                       this->sampling_.describe(), polar_ ? "polar" : "cartesian");
  }

  // The depth, radii and volumes are state too: in 2D the depth is the mean
  // diameter at the first observation, not an option.
  void save_own(DiagnosticStateWriter& w) const override {
    frame_.save(w);
    w.put_integers("counts", {volume_.empty() ? 0 : 1, window_samples_, total_samples_});
    w.put("depth", depth_);
    w.put("zone_radii", radii_);
    w.put("zone_volume", volume_);
    w.put("window_sum", window_sum_);
    w.put("total_sum", total_sum_);
  }
  void load_own(const DiagnosticStateReader& r) override {
    const auto counts = r.integers("counts", 3);
    if ((counts[0] != 0 && counts[0] != 1) || counts[1] < 0 || counts[2] < counts[1])
      r.invalid("counts", "holds impossible counts");
    const bool set_up = counts[0] == 1;
    const std::size_t z = set_up ? zones_ : 0;
    ZonesDiagnostic next = *this;  // all or nothing: a refused load leaves this as it was
    next.frame_.load(r);
    next.depth_ = r.number("depth");
    next.radii_ = r.doubles("zone_radii", set_up ? z + 1 : 0);
    next.volume_ = r.doubles("zone_volume", z);
    next.window_sum_ = r.doubles("window_sum", quantity_count * z);
    next.total_sum_ = r.doubles("total_sum", quantity_count * z);
    next.window_samples_ = counts[1], next.total_samples_ = counts[2];
    *this = std::move(next);
  }

 private:
  // The options as attached (depth 0: one mean diameter, found on the first observation).
  std::string fingerprint() const override {
    return fmt::format("{}; chamber {}; zones {}; depth {:.17g}; mean {}; label {}", name,
                       frame_.chamber_name, zones_, depth_option_, polar_ ? "polar" : "cartesian",
                       label_);
  }
  void setup(const Particles<D>& p) {
    if constexpr (D == 2) {
      if (!(depth_ > 0)) {  // one particle diameter (4.3.2): the mean over the powder
        double sum = 0;
        int n = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
          if (!p.fixed[i]) sum += 2 * p.radius[i], ++n;
        if (n == 0) throw InputError("diagnostic 'zones': no moving particles to set the depth");
        depth_ = sum / n;
      }
    }
    const double R = frame_.radius;
    radii_.resize(zones_ + 1);
    for (int k = 0; k <= zones_; ++k) radii_[k] = R * std::sqrt(static_cast<double>(k) / zones_);
    volume_.resize(zones_);
    for (int z = 0; z < zones_; ++z)
      volume_[z] = pi * (radii_[z + 1] * radii_[z + 1] - radii_[z] * radii_[z]) * depth_;
    window_sum_.assign(quantity_count * zones_, 0.0);
    total_sum_.assign(quantity_count * zones_, 0.0);
  }

  void declare() {
    if (declared_ || !sink_) return;
    declared_ = true;
    std::vector<std::string> columns{"time"};
    for (int z = 1; z <= zones_; ++z) columns.push_back(fmt::format("zone_{}", z));
    for (int q = 0; q < quantity_count; ++q) {
      const std::string g = group(q);
      sink_->declare_series(g, columns);
      sink_->write_attribute(g, "units", std::string(quantity_units[q]));
    }
    const std::string g = "diagnostics/" + label_;
    this->write_sampling_attributes(*sink_, g);
    sink_->write_attribute(g, "zone_radii", radii_);
    sink_->write_attribute(g, "zone_volume", volume_);
    sink_->write_attribute(g, "depth", depth_);
    sink_->write_attribute(g, "mean", std::string(polar_ ? "polar" : "cartesian"));
    sink_->write_attribute(g, "chamber", frame_.chamber_name);
  }
  std::string group(int q) const { return "diagnostics/" + label_ + "/" + quantity_names[q]; }

  // Zone of a radial distance (beyond the chamber: the outermost zone).
  int zone_of(double l) const {
    const double R = frame_.radius;
    int z = static_cast<int>(zones_ * (l * l) / (R * R));
    return std::clamp(z, 0, zones_ - 1);
  }
  // Volume fractions of a particle in each zone: F(r_{k+1}) - F(r_k), with
  // F(r_0) = 0 and F(r_N) = 1 so nothing is lost at the axis or the wall.
  void split(double l, double r, std::vector<double>& fraction) const {
    double below = 0;
    for (int z = 0; z < zones_; ++z) {
      const double inside = z + 1 == zones_ ? 1.0 : zone_inner_fraction(l, radii_[z + 1], r);
      fraction[z] = inside - below;
      below = inside;
    }
  }
  // Velocity in polar components (radial, azimuthal[, axial]) at x.
  V polar_components(const V& x, const V& vel) const {
    const double dx = x.x() - frame_.center.x(), dy = x.y() - frame_.center.y();
    const double l = std::sqrt(dx * dx + dy * dy);
    V u = vel;
    if (l > 0) {
      const double c = dx / l, s = dy / l;
      u.x() = c * vel.x() + s * vel.y();
      u.y() = -s * vel.x() + c * vel.y();
    }
    return u;
  }

  void close_window(double time) override {
    if (sink_ && window_samples_ > 0) {
      declare();
      for (int q = 0; q < quantity_count; ++q) {
        std::vector<double> row{time};
        for (int z = 0; z < zones_; ++z)
          row.push_back(window_sum_[q * zones_ + z] / window_samples_);
        sink_->append_series(group(q), row);
      }
    }
    std::fill(window_sum_.begin(), window_sum_.end(), 0.0);
    window_samples_ = 0;
  }

  ChamberFrame<D> frame_;
  int zones_ = 7;
  double depth_ = 0, depth_option_ = 0;
  bool polar_ = true;
  std::string label_;
  OutputSink* sink_ = nullptr;
  bool declared_ = false;
  std::vector<double> radii_, volume_, window_sum_, total_sum_;
  std::int64_t window_samples_ = 0, total_samples_ = 0;
};

}  // namespace granule
