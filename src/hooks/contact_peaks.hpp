// Per contact, the largest normal force reached (dissertation 4.6, 7.2):
// histograms per area (Figs. 7.1-7.4) and of the relative impact velocity
// derived from it through the binary-impact relation F_max = c dv (7.2,
// c = 0.02 N s/m there; for the linear loading spring c = sqrt(m* K1), which
// is 0.020 N s/m for Table 4.1), Figs. 7.5-7.8; beside it the histogram of the
// approach speed measured at first touch, to check that relation.
//
// It also accumulates the minimum coating time of 4.7: over host-host
// contacts (both particles moving) add the contact area pi a^2 with
// a = sqrt(d R) (d the largest overlap of the contact, R = R*) until the sum
// reaches the hosts' total surface sum 4 pi r^2. The text leaves two choices
// open, so all four readings are summed side by side: one patch per contact
// or one on each host (a contact marks both surfaces), and R = R* (Hertz's
// a^2 = R* d) or R = the host's radius r (for equal hosts r = 2 R*); the
// plain coating_time is the first (one patch, R*). The kept collisions can be
// handed to coating.minimum_time in Lua (keep_collisions = n).
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
class ContactPeaksDiagnostic final : public Diagnostic<D> {
 public:
  using V = Vec<D>;
  static constexpr int A = AreaSectors::count;
  static constexpr int sets = A + 1;  // the four areas, then all contacts
  // The readings of 4.7 (see the top of this file): patches per contact x radius.
  static constexpr int conventions = 4;
  static constexpr std::array<const char*, conventions> convention_names = {
      "one_patch_rstar", "two_patches_rstar", "one_patch_r", "two_patches_r"};
  static constexpr const char* name = "contact_peaks";
  static constexpr const char* doc =
      "largest normal force of each contact: histograms per area and of the impact velocity "
      "F_max / c (7.2), measured approach speeds, and the coating-time sum of pi d R over "
      "host-host contacts (4.7)";
  // No trigger: it works on the contact events of every step; the window
  // closes on the step that fills it.
  static constexpr Sampling::Defaults sampling_defaults{
      0, 0.01, "time between rows of the cumulative series"};
  static OptionDocs options() {
    OptionDocs o = ChamberFrame<D>::option_docs(true);
    for (const auto& a : AreaSectors::option_docs()) o.push_back(a);
    o.insert(o.end(),
             {{"force_max", "N", "0.1", "upper edge of the force histograms"},
              {"velocity_max", "m/s", "5", "upper edge of the velocity histograms"},
              {"force_per_velocity", "N s/m", "0.02", "c of F_max = c dv (7.2)"},
              {"bins", "-", "50", "bins per histogram (at most 100000)"},
              {"contacts", "", "all", "'all', 'particle' or 'boundary': the contacts histogrammed"},
              {"keep_collisions", "-", "0",
               "host-host collisions kept for coating.minimum_time (arrays collision_*)"},
              {"label", "", "contact_peaks", "group under /diagnostics"}});
    Sampling::add_option_docs(o, sampling_defaults);
    return o;
  }

  explicit ContactPeaksDiagnostic(DiagnosticOptions& o) : Diagnostic<D>(name) {
    frame_.read(o, true);
    sectors_.read(o);
    force_max_ = o.number_in("force_max", 0.1, 0, 1e12, "N");
    velocity_max_ = o.number_in("velocity_max", 5, 0, 1e6, "m/s");
    c_ = o.number_in("force_per_velocity", 0.02, 0, 1e12, "N s/m");
    if (!(force_max_ > 0) || !(velocity_max_ > 0) || !(c_ > 0))
      throw InputError(fmt::format("{}: force_max, velocity_max and force_per_velocity must be > 0",
                                   o.context()));
    bins_ = static_cast<int>(o.integer("bins", 50, 1, 100000));
    const std::string which = o.string("contacts", "all");
    if (which == "all") {
      which_ = 0;
    } else if (which == "particle") {
      which_ = 1;
    } else if (which == "boundary") {
      which_ = 2;
    } else {
      throw InputError(fmt::format(
          "{}: 'contacts' must be 'all', 'particle' or 'boundary', got '{}'", o.context(), which));
    }
    keep_ = static_cast<std::size_t>(o.integer("keep_collisions", 0, 0));
    this->sampling_.read(o, sampling_defaults);
    label_ = o.string("label", "contact_peaks");
    for (auto* h : {&force_hist_, &velocity_hist_, &impact_hist_})
      for (auto& set : *h) set.assign(bins_, 0.0);
  }

  typename Diagnostic<D>::Needs needs() const override { return {false, true}; }

  void attach_output(OutputSink* sink) override {
    sink_ = sink;
    declared_ = false;
  }

  void on_events(const StepView<D>& v) override {
    frame_.resolve(v.walls, name);
    const auto& p = v.particles;
    if (start_time_ < 0) {  // the first step since attaching
      start_time_ = v.time;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (!p.fixed[i]) target_area_ += 4 * pi * p.radius[i] * p.radius[i];
    }
    declare();
    last_time_ = v.time;
    for (const auto& e : v.contacts.ended) {
      // Begun before this diagnostic's first step: going on when it was attached,
      // neither its impact nor its whole peak seen. (The engine marks such contacts
      // only when the first diagnostic that follows contacts is attached.)
      if (e.begin_time < start_time_) continue;
      bool boundary = e.id_b < 0;
      if (!boundary) {
        const int ia = p.index(e.id_a), ib = p.index(e.id_b);
        boundary = (ia >= 0 && p.fixed[ia]) || (ib >= 0 && p.fixed[ib]);
      }
      if (!boundary) {  // 4.7: host-host contacts only
        ++host_collisions_;
        const int ia = p.index(e.id_a), ib = p.index(e.id_b);
        const double mean_radius =
            ia >= 0 && ib >= 0 ? 0.5 * (p.radius[ia] + p.radius[ib]) : 2 * e.effective_radius;
        const double d = std::max(0.0, e.peak_overlap);  // a^2 = d R, by each reading of R
        const std::array<double, conventions> add_area = {
            pi * d * e.effective_radius, 2 * pi * d * e.effective_radius, pi * d * mean_radius,
            2 * pi * d * mean_radius};
        for (int k = 0; k < conventions; ++k) {
          covered_by_[k] += add_area[k];
          if (!reached_by_[k] && covered_by_[k] >= target_area_) {
            reached_by_[k] = 1;
            coating_time_by_[k] = e.end_time - start_time_;
          }
        }
        if (kept_time_.size() < keep_) {
          kept_time_.push_back(e.end_time);
          kept_overlap_.push_back(e.peak_overlap);
          kept_radius_.push_back(e.effective_radius);
        }
      }
      if ((which_ == 1 && boundary) || (which_ == 2 && !boundary)) continue;
      const int area = sectors_.area_of(frame_.angle_deg(e.position));
      const double f = e.peak_normal_force;
      const double dv = f / c_;  // Eq. 7.2 solved for the impact velocity
      for (int set : {area, A}) {
        if (set < 0) continue;
        add(force_hist_[set], f, force_max_);
        add(velocity_hist_[set], dv, velocity_max_);
        add(impact_hist_[set], e.impact_velocity, velocity_max_);
        sum_force_[set] += f;
        ++counted_[set];
        if (dv > 0.1) ++above_01_[set];
        if (dv > 0.2) ++above_02_[set];
        if (dv > 1.0) ++above_10_[set];
      }
    }
  }

  std::map<std::string, double> results() const override {
    std::map<std::string, double> r;
    const double elapsed = last_time_ - start_time_;
    // The plain coating time is the first reading (one patch, R*).
    const bool reached = reached_by_[0] != 0;
    const double covered = covered_by_[0], coating_time = coating_time_by_[0];
    r["coating_reached"] = reached ? 1 : 0;
    r["coating_time"] = reached ? coating_time : 0;
    // The rate so far extrapolated (the short runs rarely cover the surface).
    r["coating_time_estimate"] =
        reached ? coating_time
                : (covered > 0 && elapsed > 0 ? target_area_ * elapsed / covered : 0);
    r["covered_fraction"] = target_area_ > 0 ? covered / target_area_ : 0;
    r["host_collisions"] = static_cast<double>(host_collisions_);
    for (int k = 0; k < conventions; ++k) {
      const std::string n = convention_names[k];
      r["coating_time_" + n] = reached_by_[k] ? coating_time_by_[k] : 0;
      r["coating_time_estimate_" + n] =
          reached_by_[k]
              ? coating_time_by_[k]
              : (covered_by_[k] > 0 && elapsed > 0 ? target_area_ * elapsed / covered_by_[k] : 0);
      r["covered_fraction_" + n] = target_area_ > 0 ? covered_by_[k] / target_area_ : 0;
    }
    for (int s = 0; s < sets; ++s) {
      const std::string n = set_name(s);
      const double c = static_cast<double>(counted_[s]);
      r["contacts_" + n] = c;
      r["mean_peak_force_" + n] = c > 0 ? sum_force_[s] / c : 0;
      r["fraction_over_100_mm_s_" + n] = c > 0 ? above_01_[s] / c : 0;
      r["fraction_over_200_mm_s_" + n] = c > 0 ? above_02_[s] / c : 0;
      r["fraction_over_1000_mm_s_" + n] = c > 0 ? above_10_[s] / c : 0;
    }
    return r;
  }

  std::map<std::string, std::vector<double>> arrays() const override {
    std::map<std::string, std::vector<double>> a;
    a["force_edges"] = edges(force_max_);
    a["velocity_edges"] = edges(velocity_max_);
    for (int s = 0; s < sets; ++s) {
      a["force_hist_" + set_name(s)] = force_hist_[s];
      a["velocity_hist_" + set_name(s)] = velocity_hist_[s];
      a["impact_velocity_hist_" + set_name(s)] = impact_hist_[s];
    }
    if (keep_ > 0) {
      a["collision_time"] = kept_time_;
      a["collision_overlap"] = kept_overlap_;
      a["collision_radius"] = kept_radius_;
    }
    return a;
  }

  const std::string& label() const override { return label_; }
  std::string describe() const override {
    return fmt::format("contact peaks in 4 areas, {} bins to {} N and {} m/s, c = {} N s/m", bins_,
                       force_max_, velocity_max_, c_);
  }

  void save_own(DiagnosticStateWriter& w) const override {
    frame_.save(w);
    w.put_integers("counts", {host_collisions_});
    w.put("times", {start_time_, last_time_});
    w.put("areas", {target_area_});
    std::vector<double> hist;
    for (const auto* h : {&force_hist_, &velocity_hist_, &impact_hist_})
      for (const auto& set : *h) hist.insert(hist.end(), set.begin(), set.end());
    w.put("histograms", std::move(hist));
    w.put("sum_force", sum_force_);
    w.put_integers("counted", counted_);
    w.put_integers("above_100_mm_s", above_01_);
    w.put_integers("above_200_mm_s", above_02_);
    w.put_integers("above_1000_mm_s", above_10_);
    w.put("conventions",
          {covered_by_[0], covered_by_[1], covered_by_[2], covered_by_[3], coating_time_by_[0],
           coating_time_by_[1], coating_time_by_[2], coating_time_by_[3]});
    w.put_integers("conventions_reached", reached_by_);
    w.put("collision_time", kept_time_);
    w.put("collision_overlap", kept_overlap_);
    w.put("collision_radius", kept_radius_);
  }
  void load_own(const DiagnosticStateReader& r) override {
    const auto counts = r.integers("counts", 1);
    if (counts[0] < 0) r.invalid("counts", "holds impossible counts");
    ContactPeaksDiagnostic next = *this;  // all or nothing: a refused load leaves this as it was
    next.frame_.load(r);
    next.host_collisions_ = counts[0];
    const auto times = r.doubles("times", 2);
    next.start_time_ = times[0], next.last_time_ = times[1];
    next.target_area_ = r.number("areas");
    const auto hist = r.doubles("histograms", 3 * sets * static_cast<std::size_t>(bins_));
    auto at = hist.begin();
    for (auto* h : {&next.force_hist_, &next.velocity_hist_, &next.impact_hist_})
      for (auto& set : *h) {
        set.assign(at, at + bins_);
        at += bins_;
      }
    r.read("sum_force", next.sum_force_);
    r.read("counted", next.counted_);
    r.read("above_100_mm_s", next.above_01_);
    r.read("above_200_mm_s", next.above_02_);
    r.read("above_1000_mm_s", next.above_10_);
    const auto by = r.doubles("conventions", 2 * conventions);
    for (int k = 0; k < conventions; ++k)
      next.covered_by_[k] = by[k], next.coating_time_by_[k] = by[conventions + k];
    r.read("conventions_reached", next.reached_by_);
    for (auto flag : next.reached_by_)
      if (flag != 0 && flag != 1)
        r.invalid("conventions_reached", "holds a flag other than 0 or 1");
    next.kept_time_ = r.doubles("collision_time", DiagnosticStateReader::any_size);
    if (next.kept_time_.size() > keep_)
      r.invalid("collision_time", fmt::format("holds {} collisions, more than keep_collisions = {}",
                                              next.kept_time_.size(), keep_));
    next.kept_overlap_ = r.doubles("collision_overlap", DiagnosticStateReader::any_size);
    next.kept_radius_ = r.doubles("collision_radius", DiagnosticStateReader::any_size);
    if (next.kept_overlap_.size() != next.kept_time_.size() ||
        next.kept_radius_.size() != next.kept_time_.size())
      r.invalid("collision_time",
                fmt::format("has {} entries, '{}collision_overlap' {} and '{}collision_radius' {}: "
                            "one per kept collision in each",
                            next.kept_time_.size(), r.prefix(), next.kept_overlap_.size(),
                            r.prefix(), next.kept_radius_.size()));
    *this = std::move(next);
  }

 private:
  static std::string set_name(int s) { return s < A ? AreaSectors::names[s] : "all"; }
  std::string fingerprint() const override {
    static const char* const contacts[] = {"all", "particle", "boundary"};
    return fmt::format(
        "{}; chamber {}; inner piece {}; sectors {:.17g}; force_max {:.17g}; velocity_max "
        "{:.17g}; force_per_velocity {:.17g}; bins {}; contacts {}; keep_collisions {}; label {}",
        name, frame_.chamber_name, frame_.inner_name, fmt::join(sectors_.bounds(), " "), force_max_,
        velocity_max_, c_, bins_, contacts[which_], keep_, label_);
  }
  std::vector<double> edges(double max) const {
    std::vector<double> e(bins_ + 1);
    for (int k = 0; k <= bins_; ++k) e[k] = max * k / bins_;
    return e;
  }
  // Linear bins on [0, max); values at or past max land in the last bin.
  void add(std::vector<double>& h, double x, double max) const {
    int k = static_cast<int>(std::floor(x / max * bins_));
    h[std::clamp(k, 0, bins_ - 1)] += 1;
  }

  void declare() {
    if (declared_ || !sink_) return;
    declared_ = true;
    const std::string g = "diagnostics/" + label_;
    std::vector<std::string> coating{"time", "covered_area", "covered_fraction", "host_collisions"};
    for (const char* n : convention_names) coating.push_back(std::string("covered_fraction_") + n);
    sink_->declare_series(g + "/coating", coating);
    std::string coating_units = "s, m^2, -, -";
    for (std::size_t k = 4; k < coating.size(); ++k) coating_units += ", -";
    sink_->write_attribute(g + "/coating", "units", coating_units);
    std::vector<std::string> columns{"time"};
    for (int k = 1; k <= bins_; ++k) columns.push_back(fmt::format("bin_{}", k));
    for (int s = 0; s < sets; ++s)
      for (const char* q :
           {"force_histogram_", "velocity_histogram_", "impact_velocity_histogram_"}) {
        sink_->declare_series(g + "/" + q + set_name(s), columns);
        sink_->write_attribute(g + "/" + q + set_name(s), "units", std::string("-"));  // counts
        sink_->write_attribute(g + "/" + q + set_name(s), "quantity", std::string(quantity(q)));
      }
    sink_->write_attribute(g, "window", this->sampling_.window());
    sink_->write_attribute(g, "force_bin_edges", edges(force_max_));
    sink_->write_attribute(g, "velocity_bin_edges", edges(velocity_max_));
    sink_->write_attribute(g, "force_per_velocity", c_);
    sink_->write_attribute(g, "target_area", target_area_);
    sink_->write_attribute(g, "area_bounds_deg", sectors_.bounds());
    sink_->write_attribute(g, "histograms", std::string("cumulative counts since attaching"));
  }

  void close_window(double time) override {
    if (sink_) {
      declare();
      const std::string g = "diagnostics/" + label_;
      std::vector<double> coating{time, covered_by_[0],
                                  target_area_ > 0 ? covered_by_[0] / target_area_ : 0,
                                  static_cast<double>(host_collisions_)};
      for (double c : covered_by_) coating.push_back(target_area_ > 0 ? c / target_area_ : 0);
      sink_->append_series(g + "/coating", coating);
      for (int s = 0; s < sets; ++s) {
        auto write = [&](const char* q, const std::vector<double>& h) {
          std::vector<double> row{time};
          row.insert(row.end(), h.begin(), h.end());
          sink_->append_series(g + "/" + q + set_name(s), row);
        };
        write("force_histogram_", force_hist_[s]);
        write("velocity_histogram_", velocity_hist_[s]);
        write("impact_velocity_histogram_", impact_hist_[s]);
      }
    }
  }

  ChamberFrame<D> frame_;
  AreaSectors sectors_;
  // What a histogram bins: "velocity" is 7.2's impact velocity F_max / c,
  // "impact_velocity" the approach speed measured at first touch.
  static const char* quantity(const std::string& histogram) {
    if (histogram.rfind("force", 0) == 0) return "largest normal force of each contact [N]";
    if (histogram.rfind("velocity", 0) == 0) return "F_max / force_per_velocity (Eq. 7.2) [m/s]";
    return "approach speed measured at first touch [m/s]";
  }
  double force_max_ = 0.1, velocity_max_ = 5, c_ = 0.02;
  int bins_ = 50, which_ = 0;
  std::size_t keep_ = 0;
  std::string label_;
  OutputSink* sink_ = nullptr;
  bool declared_ = false;
  std::array<std::vector<double>, sets> force_hist_, velocity_hist_, impact_hist_;
  std::array<double, sets> sum_force_{};
  std::array<std::int64_t, sets> counted_{}, above_01_{}, above_02_{}, above_10_{};
  double start_time_ = -1, last_time_ = 0;  // s; start < 0: no step seen yet
  double target_area_ = 0;
  std::int64_t host_collisions_ = 0;
  std::array<double, conventions> covered_by_{}, coating_time_by_{};
  std::array<std::int64_t, conventions> reached_by_{};
  std::vector<double> kept_time_, kept_overlap_, kept_radius_;
};

}  // namespace granule
