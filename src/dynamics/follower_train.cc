#include "dynamics/follower_train.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/errors.h"
#include "dynamics/dual.h"
#include "dynamics/kinematic_lift.h"
#include "dynamics/spring_stress.h"
#include "geometry/check_text.h"

namespace camdyn {

namespace {

/// A seat's or stop's force law from its config (the cam contact's laws).
ForceLaw seat_law(const SeatConfig& c) {
  ForceLaw law;
  law.model = c.model;
  law.stiffness = c.stiffness;
  law.exponent = c.exponent;
  law.restitution = c.restitution;
  law.damping = c.damping.value_or(0.0);
  law.reference_velocity = c.reference_velocity;
  return law;
}

/// Builds the train while it appends coordinates and elements.
class TrainBuilder {
 public:
  TrainBuilder(const std::string& file, StateLayout& layout, FollowerTrain& train)
      : file_(file), layout_(layout), train_(train) {}

  /// A coordinate of mass `mass` [kg] with its two states; returns its index.
  int add_coordinate(const std::string& name, double mass, const std::string& at) {
    if (layout_.size + 2 > StateLayout::kMax ||
        static_cast<int>(train_.coordinates.size()) >= TrainLimits::kMaxCoordinates)
      throw InputError(file_, at,
                       "the train needs more than " + std::to_string(StateLayout::kMaxTrain) +
                           " states: fewer bodies or spring coils");
    TrainCoordinate c;
    c.position = layout_.add_train(name + "_position");
    c.velocity = layout_.add_train(name + "_velocity");
    c.mass = mass;
    train_.coordinates.push_back(c);
    return static_cast<int>(train_.coordinates.size()) - 1;
  }

  /// Appends an element; one-sided and contact elements get a root function.
  int add(TrainElement e, const std::string& at) {
    if (e.gap_root()) {
      if (train_.roots >= TrainLimits::kMaxRoots)
        throw InputError(file_, at,
                         "the train has more than " + std::to_string(TrainLimits::kMaxRoots) +
                             " one-sided elements (links, seats, stops, coil clash segments)");
      e.root = train_.roots++;
    }
    train_.elements.push_back(e);
    return static_cast<int>(train_.elements.size()) - 1;
  }

  /// A seat (from below) or a stop (from above) on coordinate `c`.
  int add_seat(const SeatConfig& s, int body, int c, bool stop, const std::string& at) {
    TrainElement e;
    e.law = TrainElement::Law::contact;
    e.role = stop ? TrainRole::stop : TrainRole::seat;
    e.body = body;
    e.a = c;
    e.ca = stop ? 1.0 : -1.0;  // δ = p − x (seat), x − p (stop)
    e.offset = stop ? -s.position : s.position;
    e.contact = seat_law(s);
    return add(e, at);
  }

  /// The gas load of body `body` on coordinate `c` (docs/model.md §12, "Gas
  /// load"), its table checked: crank angles increasing within one cam turn,
  /// pressures >= 0.
  int add_gas(const GasLoadConfig& g, int body, int c, const std::string& at) {
    GasLoad load{g.area, g.crank_ratio, g.tdc_deg, g.port_pressure, g.crank_deg, g.pressure_pa};
    const auto line = [&](std::size_t i) {
      return i < g.lines.size() ? " (" + g.pressure + " line " + std::to_string(g.lines[i]) + ")" : std::string();
    };
    if (load.crank_deg.size() < 2 || load.crank_deg.size() != load.pressure.size())
      throw InputError(file_, at + ".pressure", "the pressure table needs at least 2 rows of crank_deg and pressure");
    for (std::size_t i = 0; i < load.crank_deg.size(); ++i) {
      if (i > 0 && !(load.crank_deg[i] > load.crank_deg[i - 1]))
        throw InputError(file_, at + ".pressure", "crank_deg must increase from row to row" + line(i));
      if (!(load.pressure[i] >= 0.0))
        throw InputError(file_, at + ".pressure", "a pressure is an absolute pressure >= 0 [Pa]" + line(i));
    }
    if (!(load.crank_deg.back() - load.crank_deg.front() < load.period_deg()))
      throw InputError(file_, at + ".pressure",
                       "the table spans " + check_text::num(load.crank_deg.back() - load.crank_deg.front()) +
                           " crank degrees, not less than one cam turn (360 x crank_ratio = " +
                           check_text::num(load.period_deg()) + ")");
    TrainElement e;
    e.law = TrainElement::Law::gas;
    e.role = TrainRole::gas;
    e.body = body;
    e.a = c;
    e.ca = 1.0;  // pushes the body down, against its opening
    e.gas = static_cast<int>(train_.gas_loads.size());
    train_.gas_loads.push_back(std::move(load));
    return add(e, at);
  }

  /// The spring of body `body` on coordinate `c` (docs/model.md §12): massless
  /// (F₀ + k x) or lumped in `lumps` masses (`coils` without it), each of its
  /// segments with its share of the clash clearance. Returns its frame-end element.
  int add_spring(const SpringConfig& s, const std::string& name, int body, int c, const std::string& at) {
    TrainElement e;
    e.role = TrainRole::spring;
    e.body = body;
    e.preload = s.preload;
    if (!s.massive()) {
      e.a = c;
      e.ca = 1.0;
      e.stiffness = s.stiffness;
      return add(e, at);
    }
    const int n = s.lump_count();
    const std::string lumps_at = at + (s.lumps ? ".lumps" : ".coils");
    const double m_s = *s.mass, k_s = (n + 1) * s.stiffness;  // [kg], [N/m]
    // First fixed-fixed mode of the chain, and stiffness-proportional damping giving it ratio ζ.
    const double omega1 = 2.0 * std::sqrt(k_s * n / m_s) * std::sin(std::numbers::pi / (2.0 * (n + 1)));
    const double c_s = 2.0 * s.damping_ratio.value_or(SpringConfig::kDefaultDampingRatio) * k_s / omega1;
    int previous = c, end = -1;
    for (int j = 1; j <= n + 1; ++j) {
      const int next = j <= n ? add_coordinate(name + "_spring_lump" + std::to_string(j), m_s / n, lumps_at) : -1;
      TrainElement seg = e;
      seg.role = j <= n ? TrainRole::spring_segment : TrainRole::spring;
      seg.a = previous;
      seg.ca = 1.0;
      seg.b = next;
      seg.cb = next >= 0 ? -1.0 : 0.0;
      seg.stiffness = k_s;
      seg.damping = c_s;
      end = add(seg, at);
      if (s.clash) {
        TrainElement clash = seg;
        clash.law = TrainElement::Law::one_sided;
        clash.role = TrainRole::clash;
        clash.preload = 0.0;
        clash.offset = -s.segment_clash_gap();
        clash.stiffness = s.clash->stiffness;
        clash.damping = 0.0;
        add(clash, at + ".clash");
      }
      previous = next;
    }
    return end;
  }

 private:
  const std::string& file_;
  StateLayout& layout_;
  FollowerTrain& train_;
};

/// A body's seat, stop and spring (`spring_here`: the spring is the train's,
/// not a massless follower spring left in FollowerForces).
void add_body_supports(TrainBuilder& b, TrainBody& body, int index, const SpringConfig* spring,
                       const std::optional<SeatConfig>& seat, const std::optional<SeatConfig>& stop,
                       const std::string& at) {
  if (seat) body.seat = b.add_seat(*seat, index, body.coordinate, false, at + ".seat");
  if (stop) body.stop = b.add_seat(*stop, index, body.coordinate, true, at + ".stop");
  if (spring) {
    body.spring_end = b.add_spring(*spring, body.name, index, body.coordinate, at + ".spring");
    if (spring->massive()) {
      body.spring_coils = spring->coils.value_or(1);
      body.spring_lumps = spring->lump_count();
    }
    if (spring->wire_diameter && spring->mean_diameter)
      body.spring_stress_per_newton = wahl_stress_per_newton(*spring->wire_diameter, *spring->mean_diameter);
  }
}

/// `lash` [m]: the link's (follower.lash may have set it, place_lash).
void add_train_body(TrainBuilder& b, FollowerTrain& train, const TrainBodyConfig& c, int index, double lash) {
  const std::string at = "mechanism.train[" + std::to_string(index - 1) + "]";
  TrainBody body;
  body.name = c.name;
  body.coordinate = b.add_coordinate(c.name, c.mass, at);
  body.ratio = c.link.ratio;
  body.lash = c.link.one_sided ? lash : 0.0;
  TrainElement link;
  link.law = c.link.one_sided ? TrainElement::Law::one_sided : TrainElement::Law::spring;
  link.role = TrainRole::link;
  link.body = index;
  link.a = train.bodies.back().coordinate;
  link.ca = c.link.ratio;
  link.b = body.coordinate;
  link.cb = -1.0;
  link.offset = -body.lash;
  link.stiffness = c.link.stiffness;
  link.damping = c.link.damping;
  body.link = b.add(link, at + ".link");
  if (c.damping > 0.0) {
    TrainElement damper;
    damper.role = TrainRole::damper;
    damper.body = index;
    damper.a = body.coordinate;
    damper.ca = 1.0;
    damper.damping = c.damping;
    b.add(damper, at + ".damping");
  }
  const bool spring = c.spring.stiffness > 0.0 || c.spring.preload > 0.0 || c.spring.massive();
  train.bodies.push_back(body);
  add_body_supports(b, train.bodies.back(), index, spring ? &c.spring : nullptr, c.seat, c.stop, at);
  if (c.gas) train.bodies.back().gas = b.add_gas(*c.gas, index, body.coordinate, at + ".gas");
}

/// F, ∂F/∂d, ∂F/∂ḋ of an element at (d, ḋ).
struct ElementForce {
  double force = 0.0, d_d = 0.0, d_v = 0.0;
};

ElementForce element_force(const TrainElement& e, double d, double d_rate, double v0, bool partials) {
  ElementForce f;
  switch (e.law) {
    case TrainElement::Law::spring:
      f.force = e.preload + e.stiffness * d + e.damping * d_rate;
      f.d_d = e.stiffness;
      f.d_v = e.damping;
      break;
    case TrainElement::Law::one_sided: {
      const double unclamped = e.stiffness * d + e.damping * d_rate;
      if (d > 0.0 && unclamped > 0.0) {
        f.force = unclamped;
        f.d_d = e.stiffness;
        f.d_v = e.damping;
      }
      break;
    }
    case TrainElement::Law::contact:
      if (partials) {
        const Dual<2> F = e.contact.force_t(Dual<2>::variable(d, 0), Dual<2>::variable(d_rate, 1), v0);
        f.force = F.v;
        f.d_d = F.d[0];
        f.d_v = F.d[1];
      } else {
        f.force = e.contact.force(d, d_rate, v0);
      }
      break;
    case TrainElement::Law::gas:  // given against the cam angle, not d: gas_force()
      break;
  }
  return f;
}

/// A gas element's force at the cam angle θ [rad], and its ∂F/∂θ into `d_theta` if given.
double gas_force(const FollowerTrain& train, const TrainElement& e, double theta, double* d_theta = nullptr) {
  return train.gas_loads[static_cast<std::size_t>(e.gas)].force(theta, d_theta);
}

/// Compression d and its rate of an element at the state x.
void compression(const TrainElement& e, const double* x, double& d, double& d_rate) {
  d = e.offset;
  d_rate = 0.0;
  if (e.a >= 0) {
    d += e.ca * x[e.position_a];
    d_rate += e.ca * x[e.velocity_a];
  }
  if (e.b >= 0) {
    d += e.cb * x[e.position_b];
    d_rate += e.cb * x[e.velocity_b];
  }
}

/// The state indices and the rest energy of every element (TrainElement's derived fields).
void derive_element_constants(FollowerTrain& train) {
  for (TrainElement& e : train.elements) {
    if (e.a >= 0) {
      e.position_a = train.coordinates[static_cast<std::size_t>(e.a)].position;
      e.velocity_a = train.coordinates[static_cast<std::size_t>(e.a)].velocity;
    }
    if (e.b >= 0) {
      e.position_b = train.coordinates[static_cast<std::size_t>(e.b)].position;
      e.velocity_b = train.coordinates[static_cast<std::size_t>(e.b)].velocity;
    }
    e.rest_energy = e.stiffness > 0.0 ? 0.5 * e.preload * e.preload / e.stiffness : 0.0;
  }
}

/// Stored energy [J] and dissipated power [W] of an element.
void element_energy(const TrainElement& e, double d, double d_rate, double force, TrainEvaluation& out) {
  switch (e.law) {
    case TrainElement::Law::spring:
      // From the free length, so that it is never negative (as the follower's spring).
      out.potential += e.preload * d + 0.5 * e.stiffness * d * d + e.rest_energy;
      out.power_damper += e.damping * d_rate * d_rate;
      break;
    case TrainElement::Law::one_sided:
      if (d > 0.0) {
        out.potential += 0.5 * e.stiffness * d * d;
        out.power_hysteresis += (force - e.stiffness * d) * d_rate;
      }
      break;
    case TrainElement::Law::contact:
      if (d > 0.0) {
        out.potential += e.contact.elastic_energy(d);
        out.power_hysteresis += (force - e.contact.elastic_force(d)) * d_rate;
      }
      break;
    case TrainElement::Law::gas:
      out.power_external -= force * d_rate;  // the bodies receive −c F: power −F ḋ
      break;
  }
}

/// The element's force into the body outputs it belongs to.
void element_outputs(const TrainElement& e, double d, double force, TrainEvaluation& out) {
  const auto i = static_cast<std::size_t>(e.body);
  switch (e.role) {
    case TrainRole::link:
      out.link_force[i] = force;
      break;
    case TrainRole::seat:
      out.seat_force[i] = force;
      out.seated[i] = d > 0.0;
      break;
    case TrainRole::stop:
      out.stop_force[i] = force;
      break;
    case TrainRole::spring:
      out.spring_force[i] = force;
      break;
    case TrainRole::gas:
      out.gas_force[i] = force;
      break;
    default:
      break;
  }
}

}  // namespace

double GasLoad::force(double theta, double* d_theta) const {
  // The crank angle within [φ₀, φ₀ + P), φ₀ the first row, P one cam turn.
  const double period = period_deg(), first = crank_deg.front();
  double phi = crank_ratio * (theta * (180.0 / std::numbers::pi) - tdc_deg);
  phi = first + std::fmod(phi - first, period);
  if (phi < first) phi += period;
  // The segment [row i, row i + 1], the last one closing the cycle to the first row a period on.
  const auto next = std::upper_bound(crank_deg.begin(), crank_deg.end(), phi);
  const std::size_t i = static_cast<std::size_t>(next - crank_deg.begin()) - 1;
  const bool closing = i + 1 == crank_deg.size();
  const double x0 = crank_deg[i], x1 = closing ? first + period : crank_deg[i + 1];
  const double p0 = pressure[i], p1 = closing ? pressure.front() : pressure[i + 1];
  const double slope = (p1 - p0) / (x1 - x0);  // [Pa/deg]
  if (d_theta) *d_theta = area * slope * crank_ratio * (180.0 / std::numbers::pi);
  return area * (p0 + slope * (phi - x0) - port_pressure);
}

bool FollowerTrain::has_seat() const {
  return std::any_of(bodies.begin(), bodies.end(), [](const TrainBody& b) { return b.seat >= 0; });
}

bool FollowerTrain::rests_on_seat(const TrainEvaluation& e, int body) const {
  for (std::size_t i = static_cast<std::size_t>(body); i < bodies.size(); ++i) {
    if (e.seated[i]) return true;
    if (i + 1 == bodies.size()) return false;
    const int link = bodies[i + 1].link;
    if (link < 0) return false;
    const int root = elements[static_cast<std::size_t>(link)].root;
    if (root >= 0 && e.gap[static_cast<std::size_t>(root)] > 0.0) return false;  // the link to the next body is open
  }
  return false;
}

namespace {

/// The follower's seat and the links' lash once `mechanism.follower.lash`
/// is placed (docs/config.md, "follower.lash").
struct PlacedLash {
  std::optional<SeatConfig> follower_seat;
  std::vector<double> link_lash;  ///< per train body [m]
};

/// Puts `follower.lash` λ on the existing elements when the chain from the
/// cam to the first seated train body carries no lash of its own (the
/// follower's seat at position 0 or absent, the links up to that body
/// without lash): without a seated train body, the follower rests on its
/// seat (the `seat` block's law, else FollowerConfig::default_lash_seat()) at
/// position λ; with one, body k, the link into it gets the lash r₁ ⋯ r_k λ,
/// so that the cam travels λ from the base circle before body k leaves its
/// seat. A chain with a lash of its own is kept as given, and follower.lash
/// only checks it (the lash_mismatch warning, dynamics/plausibility.cc).
PlacedLash place_lash(const MechanismConfig& mech, const std::string& file) {
  const FollowerConfig& f = mech.follower;
  PlacedLash placed;
  placed.follower_seat = f.seat;
  for (const TrainBodyConfig& body : mech.train) placed.link_lash.push_back(body.link.lash);
  if (!f.lash) return placed;
  const auto seated = std::find_if(mech.train.begin(), mech.train.end(), [](const auto& b) { return b.seat; });
  const auto k = seated - mech.train.begin();  // the seated body's index, or the train's size
  const auto chain_end = seated == mech.train.end() ? mech.train.begin() : seated + 1;
  bool own = f.seat && f.seat->position != 0.0;
  double ratio = 1.0;  // r₁ ⋯ r_k [m/m | m/rad]
  for (auto i = mech.train.begin(); i != chain_end; ++i) {
    own = own || i->link.lash != 0.0;
    ratio *= i->link.ratio;
  }
  if (own) return placed;
  const std::string at = "mechanism.follower.lash";
  if (seated == mech.train.end()) {
    if (!placed.follower_seat && f.motion == FollowerMotion::oscillating)
      throw InputError(file, at,
                       "an oscillating follower's lash needs a 'seat' block on the follower (its force law acts on "
                       "the arm angle, in N m/rad^n)");
    if (!placed.follower_seat) placed.follower_seat = FollowerConfig::default_lash_seat();
    placed.follower_seat->position = *f.lash;
    if (f.stop && !(f.stop->position > *f.lash))
      throw InputError(file, at,
                       "the follower's seat at the lash must be below its stop (stop.position = " +
                           check_text::num(f.stop->position) + ")");
    return placed;
  }
  if (!seated->link.one_sided)
    throw InputError(file, at,
                     "goes on the link into mechanism.train[" + std::to_string(k) +
                         "], the first body with a seat, which is two-sided (no lash): make that link one-sided");
  placed.link_lash[static_cast<std::size_t>(k)] = ratio * *f.lash;
  return placed;
}

/// A gas load's crank angle against the report's (`outputs.valvetrain`):
/// one crank for the table and the plots, or an error naming both.
void check_gas_crank(const SceneConfig& scene, std::size_t i, const std::string& file) {
  const std::optional<GasLoadConfig>& gas = scene.mechanism.train[i].gas;
  const std::optional<ValvetrainOutputConfig>& out = scene.outputs.valvetrain;
  if (!gas || !out || (gas->crank_ratio == out->crank_ratio && gas->tdc_deg == out->tdc_deg)) return;
  throw InputError(file, "mechanism.train[" + std::to_string(i) + "].gas",
                   "crank_ratio " + check_text::num(gas->crank_ratio) + " and tdc_deg " +
                       check_text::num(gas->tdc_deg) + " differ from outputs.valvetrain's (" +
                       check_text::num(out->crank_ratio) + ", " + check_text::num(out->tdc_deg) +
                       "): the pressure table and the report's crank angle must be one crank");
}

}  // namespace

FollowerTrain build_follower_train(const SceneConfig& scene, const std::string& file, StateLayout& layout) {
  const MechanismConfig& mech = scene.mechanism;
  const FollowerConfig& f = mech.follower;
  FollowerTrain train;
  const PlacedLash lash = place_lash(mech, file);
  const bool follower_elements = lash.follower_seat || f.stop || f.spring.massive();
  if (!follower_elements && mech.train.empty()) return train;
  TrainBuilder b(file, layout, train);
  TrainCoordinate follower;
  follower.mass = f.motion == FollowerMotion::oscillating ? f.inertia : f.mass;
  train.coordinates.push_back(follower);
  TrainBody body;
  body.name = "follower";
  train.bodies.push_back(body);
  train.follower_spring_lumped = f.spring.massive();
  add_body_supports(b, train.bodies.back(), 0, train.follower_spring_lumped ? &f.spring : nullptr, lash.follower_seat,
                    f.stop, "mechanism.follower");
  if (static_cast<int>(mech.train.size()) + 1 > TrainLimits::kMaxBodies)
    throw InputError(file, "mechanism.train",
                     "at most " + std::to_string(TrainLimits::kMaxBodies - 1) + " bodies after the follower");
  for (std::size_t i = 0; i < mech.train.size(); ++i) {
    check_gas_crank(scene, i, file);
    add_train_body(b, train, mech.train[i], static_cast<int>(i) + 1, lash.link_lash[i]);
  }
  derive_element_constants(train);
  return train;
}

TrainLash train_lash(const FollowerTrain& train) {
  TrainLash lash;
  if (train.bodies.empty()) return lash;
  const auto seat_position = [&](const TrainBody& b) {
    return train.elements[static_cast<std::size_t>(b.seat)].offset;
  };
  const bool follower_seat = train.bodies[0].seat >= 0;
  const double follower = follower_seat ? seat_position(train.bodies[0]) : 0.0;  // [m | rad]
  double ratio = 1.0, carried = 0.0;  // r₁ ⋯ rᵢ; the links' lash carried to body i, Λᵢ = rᵢ Λᵢ₋₁ + λᵢ [m]
  for (std::size_t i = 1; i < train.bodies.size(); ++i) {
    const TrainBody& b = train.bodies[i];
    ratio *= b.ratio;
    carried = b.ratio * carried + b.lash;
    if (b.seat < 0) continue;
    const double from_links = (carried + seat_position(b)) / ratio;
    lash.body = static_cast<int>(i);
    lash.at_cam = follower_seat ? std::max(follower, from_links) : from_links;
    lash.held_open = follower_seat ? std::max(0.0, ratio * (follower - from_links)) : 0.0;
    return lash;
  }
  lash.at_cam = follower;
  return lash;
}

void add_train_names(const FollowerTrain& train, std::vector<std::string>& names) {
  for (std::size_t i = 1; i < train.bodies.size(); ++i) names.push_back("body:" + train.bodies[i].name);
  for (const TrainElement& e : train.elements) {
    const std::string& body = train.bodies[static_cast<std::size_t>(e.body)].name;
    switch (e.role) {
      case TrainRole::link:
        names.push_back((e.law == TrainElement::Law::one_sided ? "link:" : "joint:") + body);
        break;
      case TrainRole::seat:
        names.push_back("seat:" + body + ":" + to_string(e.contact.model));
        break;
      case TrainRole::stop:
        names.push_back("stop:" + body + ":" + to_string(e.contact.model));
        break;
      case TrainRole::spring: {
        // "spring:valve:8_coils", and ":16_lumps" after it when lumped otherwise than one mass a coil.
        const TrainBody& owner = train.bodies[static_cast<std::size_t>(e.body)];
        std::string name = "spring:" + body;
        if (owner.spring_lumps > 0) name += ":" + std::to_string(owner.spring_coils) + "_coils";
        if (owner.spring_lumps != owner.spring_coils) name += ":" + std::to_string(owner.spring_lumps) + "_lumps";
        names.push_back(name);
        break;
      }
      case TrainRole::damper:
        names.push_back("damper:" + body);
        break;
      case TrainRole::gas:
        names.push_back("gas:" + body);
        break;
      case TrainRole::clash:
      case TrainRole::spring_segment:
        break;
    }
  }
}

void prepare_train_workspace(const FollowerTrain& train, TrainWorkspace& ws) {
  ws.v0.fill(0.0);
  for (const TrainElement& e : train.elements)
    if (e.root >= 0) ws.v0[static_cast<std::size_t>(e.root)] = e.contact.reference_velocity;
}

void evaluate_train(const FollowerTrain& train, const TrainWorkspace& ws, double theta, const double* x,
                    TrainEvaluation& e) {
  std::array<double, TrainLimits::kMaxCoordinates> force{};
  e.kinetic = e.potential = e.power_damper = e.power_hysteresis = e.power_external = 0.0;
  e.link_force.fill(0.0);
  e.seat_force.fill(0.0);
  e.stop_force.fill(0.0);
  e.spring_force.fill(0.0);
  e.gas_force.fill(0.0);
  e.spring_peak_force.fill(0.0);
  e.seated.fill(false);
  for (const TrainElement& el : train.elements) {
    double d = 0.0, d_rate = 0.0;
    compression(el, x, d, d_rate);
    double F = 0.0;
    if (el.law == TrainElement::Law::spring) {
      // The spring segments of a coil chain, most of a long train's elements:
      // element_force's and element_energy's spring case, inline.
      F = el.preload + el.stiffness * d + el.damping * d_rate;
      e.potential += el.preload * d + 0.5 * el.stiffness * d * d + el.rest_energy;
      e.power_damper += el.damping * d_rate * d_rate;
      if (el.role == TrainRole::spring_segment || el.role == TrainRole::spring) {
        double& peak = e.spring_peak_force[static_cast<std::size_t>(el.body)];
        peak = std::max(peak, std::abs(F));
      }
    } else if (el.law == TrainElement::Law::gas) {
      F = gas_force(train, el, theta);
      element_energy(el, d, d_rate, F, e);
    } else {
      const auto root = static_cast<std::size_t>(el.root);
      F = element_force(el, d, d_rate, ws.v0[root], false).force;
      e.gap[root] = -d;
      e.gap_rate[root] = -d_rate;
      element_energy(el, d, d_rate, F, e);
    }
    if (el.a >= 0) force[static_cast<std::size_t>(el.a)] -= el.ca * F;
    if (el.b >= 0) force[static_cast<std::size_t>(el.b)] -= el.cb * F;
    if (el.role != TrainRole::spring_segment) element_outputs(el, d, F, e);
  }
  e.follower_force = force[0];
  for (std::size_t c = 1; c < train.coordinates.size(); ++c) {
    const TrainCoordinate& tc = train.coordinates[c];
    const double v = x[tc.velocity];
    e.rate[c] = v;
    e.acceleration[c] = force[c] / tc.mass;
    e.kinetic += 0.5 * tc.mass * v * v;
  }
  for (std::size_t i = 0; i < train.bodies.size(); ++i) {
    const TrainCoordinate& tc = train.coordinates[static_cast<std::size_t>(train.bodies[i].coordinate)];
    e.position[i] = x[tc.position];
    e.velocity[i] = x[tc.velocity];
  }
}

void train_state_derivative(const FollowerTrain& train, const TrainEvaluation& e, double* x_dot) {
  for (std::size_t c = 1; c < train.coordinates.size(); ++c) {
    const TrainCoordinate& tc = train.coordinates[c];
    x_dot[tc.position] = e.rate[c];
    x_dot[tc.velocity] = e.acceleration[c];
  }
}

void add_train_jacobian(const FollowerTrain& train, const TrainWorkspace& ws, double theta, int cam_angle_state,
                        const double* x, int n, double* jacobian) {
  const auto at = [&](int row, int col) -> double& {
    return jacobian[static_cast<std::size_t>(row) + static_cast<std::size_t>(n) * static_cast<std::size_t>(col)];
  };
  for (std::size_t c = 1; c < train.coordinates.size(); ++c)
    at(train.coordinates[c].position, train.coordinates[c].velocity) += 1.0;
  for (const TrainElement& el : train.elements) {
    if (el.law == TrainElement::Law::gas) {  // F(θ): only a shaft's cam angle state moves it
      if (cam_angle_state < 0) continue;
      double d_theta = 0.0;
      gas_force(train, el, theta, &d_theta);
      const TrainCoordinate& row = train.coordinates[static_cast<std::size_t>(el.a)];
      at(row.velocity, cam_angle_state) -= el.ca * d_theta / row.mass;
      continue;
    }
    double d = 0.0, d_rate = 0.0;
    compression(el, x, d, d_rate);
    const double v0 = el.root >= 0 ? ws.v0[static_cast<std::size_t>(el.root)] : 0.0;
    const ElementForce f = element_force(el, d, d_rate, v0, true);
    const int ends[2] = {el.a, el.b};
    const double coefficients[2] = {el.ca, el.cb};
    for (int p = 0; p < 2; ++p) {
      if (ends[p] < 0) continue;
      const TrainCoordinate& row = train.coordinates[static_cast<std::size_t>(ends[p])];
      for (int q = 0; q < 2; ++q) {
        if (ends[q] < 0) continue;
        const TrainCoordinate& col = train.coordinates[static_cast<std::size_t>(ends[q])];
        const double scale = -coefficients[p] * coefficients[q] / row.mass;
        at(row.velocity, col.position) += scale * f.d_d;
        at(row.velocity, col.velocity) += scale * f.d_v;
      }
    }
  }
}

namespace {

/// Static force on every train coordinate at x (velocities zero) and its
/// stiffness ∂force/∂position over the coordinates 1… (index c − 1).
void static_forces(const FollowerTrain& train, const TrainWorkspace& ws, double theta, const double* x,
                   Eigen::VectorXd& force, Eigen::MatrixXd& stiffness) {
  force.setZero();
  stiffness.setZero();
  for (const TrainElement& el : train.elements) {
    double d = 0.0, d_rate = 0.0;
    compression(el, x, d, d_rate);
    const double v0 = el.root >= 0 ? ws.v0[static_cast<std::size_t>(el.root)] : 1.0;
    ElementForce f = element_force(el, d, 0.0, v0, true);
    if (el.law == TrainElement::Law::gas) f.force = gas_force(train, el, theta);
    const int ends[2] = {el.a, el.b};
    const double coefficients[2] = {el.ca, el.cb};
    for (int p = 0; p < 2; ++p) {
      if (ends[p] < 1) continue;
      force[ends[p] - 1] -= coefficients[p] * f.force;
      for (int q = 0; q < 2; ++q)
        if (ends[q] >= 1) stiffness(ends[p] - 1, ends[q] - 1) -= coefficients[p] * coefficients[q] * f.d_d;
    }
  }
}

/// The coordinates' kinematic positions: each body at its link's ratio times
/// the one before less the lash, held by its seat; spring lumps at rest.
void kinematic_positions(const FollowerTrain& train, double* x) {
  for (std::size_t c = 1; c < train.coordinates.size(); ++c) x[train.coordinates[c].position] = 0.0;
  double before = x[0];
  for (std::size_t i = 1; i < train.bodies.size(); ++i) {
    const TrainBody& b = train.bodies[i];
    const double position = lift_step(train, i).carry(before);
    x[train.coordinates[static_cast<std::size_t>(b.coordinate)].position] = position;
    before = position;
  }
  for (std::size_t c = 1; c < train.coordinates.size(); ++c) x[train.coordinates[c].velocity] = 0.0;
}

}  // namespace

bool train_static_state(const FollowerTrain& train, const TrainWorkspace& ws, double theta, double* x) {
  kinematic_positions(train, x);
  const int n = static_cast<int>(train.coordinates.size()) - 1;
  if (n == 0) return true;
  Eigen::VectorXd force(n), step(n);
  Eigen::MatrixXd stiffness(n, n);
  double scale = 0.0;  // [N/m], for the convergence test and the regularisation
  for (const TrainElement& el : train.elements) scale = std::max(scale, el.stiffness + el.contact.stiffness);
  for (int it = 0; it < 100; ++it) {
    static_forces(train, ws, theta, x, force, stiffness);
    if (force.cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, scale * 1e-6)) return true;
    stiffness.diagonal().array() -= 1e-12 * scale;  // a coordinate held by an open one-sided element only
    step = stiffness.fullPivLu().solve(-force);
    if (!step.allFinite()) break;
    // Limit a step to 0.1 mm: one-sided elements make the force piecewise.
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > 1e-4) step *= 1e-4 / largest;
    for (int c = 0; c < n; ++c) x[train.coordinates[static_cast<std::size_t>(c) + 1].position] += step[c];
    if (largest < 1e-15) return true;
  }
  kinematic_positions(train, x);
  return false;
}

int train_jacobian_bandwidth(const FollowerTrain& train, int core_size) {
  int band = core_size - 1;
  const auto couple = [&](int c, int d) {  // the rows of coordinate c's rates against d's states
    const TrainCoordinate& a = train.coordinates[static_cast<std::size_t>(c)];
    const TrainCoordinate& b = train.coordinates[static_cast<std::size_t>(d)];
    for (int row : {a.position, a.velocity})
      for (int col : {b.position, b.velocity}) band = std::max(band, std::abs(row - col));
  };
  for (std::size_t c = 1; c < train.coordinates.size(); ++c) couple(static_cast<int>(c), static_cast<int>(c));
  for (const TrainElement& e : train.elements)
    if (e.a >= 0 && e.b >= 0) {
      couple(e.a, e.b);
      couple(e.b, e.a);
    }
  return band;
}

void record_train_onset(const FollowerTrain& train, TrainWorkspace& ws, int root, double approach) {
  const TrainElement& e = train_element_of_root(train, root);
  ws.v0[static_cast<std::size_t>(root)] = std::max(approach, e.contact.reference_velocity);
}

const TrainElement& train_element_of_root(const FollowerTrain& train, int root) {
  for (const TrainElement& e : train.elements)
    if (e.root == root) return e;
  throw std::logic_error("train_element_of_root: no element has root " + std::to_string(root));
}

}  // namespace camdyn
