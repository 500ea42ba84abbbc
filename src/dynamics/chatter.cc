#include "dynamics/chatter.h"

#include <algorithm>
#include <cmath>

namespace camdyn {

namespace {

// One flight: from a separation to the impact that ends it [s].
struct Flight {
  double take_off = 0.0, landing = 0.0;
  double landing_deg = 0.0;    ///< cam angle at the landing [deg]
  double contact_after = 0.0;  ///< time on the cam after the landing, to the next separation or the run's end [s]
  double duration() const { return landing - take_off; }
};

// The flights of a run, in order (a separation followed by an impact).
std::vector<Flight> flights_of(const std::vector<ContactEvent>& events, double t_end) {
  std::vector<Flight> flights;
  double take_off = -1.0;
  for (const ContactEvent& e : events) {
    if (!e.onset) {
      if (!flights.empty() && flights.back().contact_after < 0.0)
        flights.back().contact_after = e.time - flights.back().landing;
      take_off = e.time;
    } else if (e.impact && take_off >= 0.0) {
      flights.push_back({take_off, e.time, e.cam_angle_deg, -1.0});
      take_off = -1.0;
    }
  }
  if (!flights.empty() && flights.back().contact_after < 0.0)
    flights.back().contact_after = t_end - flights.back().landing;
  return flights;
}

// Whether flight k + 1 continues a shrinking sequence at flight k: shorter,
// after no more than a brief contact (a stick between them ends a sequence).
bool shrinks(const std::vector<Flight>& f, std::size_t k) {
  const double ratio = f[k + 1].duration() / f[k].duration();
  return f[k].contact_after < 3.0 * f[k].duration() && ratio > 0.0 && ratio < 0.95;
}

// The longest run of flights a..b (b − a ≥ min_ratios) inside i..j whose
// successive ratios agree within a factor 1.5; false if there is none.
bool agreeing_run(const std::vector<Flight>& f, std::size_t i, std::size_t j, std::size_t min_ratios, std::size_t& a,
                  std::size_t& b) {
  bool found = false;
  for (std::size_t lo_k = i; lo_k < j; ++lo_k) {
    double lo = 1.0, hi = 0.0;
    for (std::size_t k = lo_k; k < j; ++k) {
      const double r = f[k + 1].duration() / f[k].duration();
      lo = std::min(lo, r);
      hi = std::max(hi, r);
      if (hi / lo >= 1.5) break;
      if (k + 1 - lo_k >= min_ratios && (!found || k + 1 - lo_k > b - a)) {
        a = lo_k;
        b = k + 1;
        found = true;
      }
    }
  }
  return found;
}

// Time on the cam after flight b's landing before a flight as long as flight b starts [s].
double settled_time(const std::vector<Flight>& f, std::size_t b, double t_end) {
  for (std::size_t m = b + 1; m < f.size(); ++m)
    if (f[m].duration() >= f[b].duration()) return f[m].take_off - f[b].landing;
  return t_end - f[b].landing;
}

}  // namespace

std::vector<ChatterSequence> find_chatter(const std::vector<ContactEvent>& events, double t_end, double deg_per_s,
                                          std::size_t min_impacts) {
  const std::vector<Flight> f = flights_of(events, t_end);
  std::vector<ChatterSequence> found;
  for (std::size_t i = 0; i + 1 < f.size();) {
    std::size_t j = i;
    while (j + 1 < f.size() && shrinks(f, j)) ++j;
    std::size_t a = 0, b = 0;
    if (j > i && agreeing_run(f, i, j, std::max<std::size_t>(min_impacts, 2) - 1, a, b) &&
        settled_time(f, b, t_end) > 3.0 * f[b].duration()) {
      double log_sum = 0.0;
      for (std::size_t k = a; k < b; ++k) log_sum += std::log(f[k + 1].duration() / f[k].duration());
      ChatterSequence c;
      c.impacts = b - a + 1;
      c.ratio = std::exp(log_sum / static_cast<double>(b - a));
      c.first_impact_time = f[a].landing;
      c.accumulation_time = f[b].landing + f[b].duration() * c.ratio / (1.0 - c.ratio);
      c.accumulation_deg = std::fmod(f[b].landing_deg + deg_per_s * (c.accumulation_time - f[b].landing), 360.0);
      if (c.accumulation_deg < 0.0) c.accumulation_deg += 360.0;
      found.push_back(c);
    }
    i = j + 1;
  }
  return found;
}

}  // namespace camdyn
