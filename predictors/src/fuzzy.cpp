#include "predvs/predictors/fuzzy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace fuzzy {

MembershipFunction MembershipFunction::trapezoid(double a, double b, double c, double d) {
  if (!(a <= b && b <= c && c <= d && a < d) || !std::isfinite(a) || !std::isfinite(d)) {
    std::ostringstream msg;
    msg << "fuzzy membership function: need finite a <= b <= c <= d with a < d, got (" << a << ", " << b << ", "
        << c << ", " << d << ")";
    throw std::invalid_argument(msg.str());
  }
  return MembershipFunction(a, b, c, d);
}

MembershipFunction MembershipFunction::triangle(double a, double b, double c) { return trapezoid(a, b, b, c); }

Variable::Variable(std::string name, double lo, double hi) : name_(std::move(name)), lo_(lo), hi_(hi) {
  if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
    throw std::invalid_argument("fuzzy variable '" + name_ + "': universe needs finite lo < hi");
}

int Variable::addSet(const std::string& name, const MembershipFunction& mf) {
  if (size() >= kMaxSets)
    throw std::invalid_argument("fuzzy variable '" + name_ + "': at most " + std::to_string(kMaxSets) + " sets");
  sets_.push_back(mf);
  set_names_.push_back(name);
  return size() - 1;
}

int Variable::indexOf(const std::string& name) const {
  for (int i = 0; i < size(); ++i)
    if (set_names_[static_cast<size_t>(i)] == name) return i;
  throw std::invalid_argument("fuzzy variable '" + name_ + "' has no set '" + name + "'");
}

double Variable::clamp(double x) const { return std::min(std::max(x, lo_), hi_); }

MamdaniSystem::MamdaniSystem(std::vector<Variable> input_vars, Variable output_var)
    : inputs_(std::move(input_vars)), output_(std::move(output_var)), fallback_(0.5 * (output_.lo() + output_.hi())) {
  if (inputs_.empty() || inputs() > kMaxInputs)
    throw std::invalid_argument("fuzzy system: needs 1 to " + std::to_string(kMaxInputs) + " inputs");
  for (const auto& v : inputs_)
    if (v.size() == 0) throw std::invalid_argument("fuzzy system: input '" + v.name() + "' has no sets");
  if (output_.size() == 0) throw std::invalid_argument("fuzzy system: output '" + output_.name() + "' has no sets");
  n_inputs_ = inputs();
  for (int i = 0; i < n_inputs_; ++i) {
    const Variable& v = inputs_[static_cast<size_t>(i)];
    FlatInput& f = flat_inputs_[static_cast<size_t>(i)];
    f.lo = v.lo();
    f.hi = v.hi();
    f.n_sets = v.size();
    for (int s = 0; s < v.size(); ++s) f.sets[static_cast<size_t>(s)] = v.set(s);
  }
  std::array<MembershipFunction, kMaxSets> out;
  for (int s = 0; s < output_.size(); ++s) out[static_cast<size_t>(s)] = output_.set(s);
  centroid_ = CentroidTable(out.data(), output_.size(), output_.lo(), output_.hi());
}

void MamdaniSystem::addRule(const std::vector<int>& antecedent, int consequent) {
  if (static_cast<int>(antecedent.size()) != inputs())
    throw std::invalid_argument("fuzzy rule: expected " + std::to_string(inputs()) + " antecedents");
  if (consequent < 0 || consequent >= output_.size())
    throw std::invalid_argument("fuzzy rule: output set index out of range");
  Rule r{};
  r.antecedent.fill(kAny);
  for (int i = 0; i < inputs(); ++i) {
    const int a = antecedent[static_cast<size_t>(i)];
    if (a != kAny && (a < 0 || a >= inputs_[static_cast<size_t>(i)].size()))
      throw std::invalid_argument("fuzzy rule: set index out of range for input '" +
                                  inputs_[static_cast<size_t>(i)].name() + "'");
    r.antecedent[static_cast<size_t>(i)] = a;
  }
  r.consequent = consequent;
  rules_.push_back(r);
}

void MamdaniSystem::addRule(const std::vector<std::string>& antecedent, const std::string& consequent) {
  if (static_cast<int>(antecedent.size()) != inputs())
    throw std::invalid_argument("fuzzy rule: expected " + std::to_string(inputs()) + " antecedents");
  std::vector<int> idx;
  for (int i = 0; i < inputs(); ++i) {
    const std::string& s = antecedent[static_cast<size_t>(i)];
    idx.push_back(s == "*" ? kAny : inputs_[static_cast<size_t>(i)].indexOf(s));
  }
  addRule(idx, output_.indexOf(consequent));
}

std::array<double, kMaxSets> MamdaniSystem::activation(const double* x) const {
  // Memberships of every (clamped) input in each of its sets, from the fixed-size copies made at
  // construction (no bounds-checked look-ups on this path). Slot kMaxSets holds 1, the neutral
  // element of the AND, and stands for kAny.
  std::array<std::array<double, kMaxSets + 1>, kMaxInputs> mu;
  for (int i = 0; i < n_inputs_; ++i) {
    const FlatInput& v = flat_inputs_[static_cast<size_t>(i)];
    auto& mu_i = mu[static_cast<size_t>(i)];
    const double xi = std::min(std::max(x[i], v.lo), v.hi);
    for (int s = 0; s < v.n_sets; ++s) mu_i[static_cast<size_t>(s)] = v.sets[static_cast<size_t>(s)](xi);
    mu_i[kMaxSets] = 1.0;
  }
  std::array<double, kMaxSets> w{};
  for (const Rule& r : rules_) {
    double strength = 1.0;  // AND = min
    for (int i = 0; i < n_inputs_; ++i) {
      const int a = r.antecedent[static_cast<size_t>(i)];
      strength = std::min(strength, mu[static_cast<size_t>(i)][static_cast<size_t>(a == kAny ? kMaxSets : a)]);
    }
    double& wc = w[static_cast<size_t>(r.consequent)];
    wc = std::max(wc, strength);  // aggregation = max
  }
  return w;
}

double MamdaniSystem::evaluate(const double* x) const {
  const std::array<double, kMaxSets> w = activation(x);
  const double y = centroid_.centroid(w.data());
  return std::isfinite(y) ? y : fallback_;
}

double MamdaniSystem::evaluate(std::initializer_list<double> x) const {
  if (static_cast<int>(x.size()) != inputs())
    throw std::invalid_argument("fuzzy system: expected " + std::to_string(inputs()) + " inputs");
  return evaluate(x.begin());
}

// ---------------------------------------------------------------------------------------------
// Analytic centroid.

namespace {

/// In-place ascending sort of a short array (a handful of entries here, where insertion sort
/// beats std::sort and needs no extra memory).
void sortShort(double* v, int n) {
  for (int i = 1; i < n; ++i) {
    const double key = v[i];
    int j = i - 1;
    for (; j >= 0 && v[j] > key; --j) v[j + 1] = v[j];
    v[j + 1] = key;
  }
}

inline double clampUnit(double t) { return std::min(std::max(t, 0.0), 1.0); }

/// Exact integrals of a linear f, f0 at x0 and f1 at x1, over [x0, x1], kept as twice the area and
/// six times the first moment (the constant factors are applied once, in the centroid).
struct Integral {
  double area2 = 0.0, moment6 = 0.0;
  Integral& operator+=(const Integral& o) {
    area2 += o.area2;
    moment6 += o.moment6;
    return *this;
  }
};
inline Integral linearIntegral(double x0, double x1, double f0, double f1) {
  const double dx = x1 - x0;
  return {(f0 + f1) * dx, dx * (x0 * (2.0 * f0 + f1) + x1 * (f0 + 2.0 * f1))};
}
inline Integral operator+(Integral a, const Integral& b) { return a += b; }

using Piece = CentroidTable::Piece;
using Interval = CentroidTable::Interval;

// The fast paths below (one set, two sets of opposite slopes) use min / max and selects instead of
// data-dependent branches: a kink that falls outside its range is clamped onto an end, which only
// creates a piece of zero width, and that adds exactly 0.

/// Integral of the clipped line g(t) = min(w, u + t (v - u)) over the part [t0, t1] of the interval.
/// g has at most one kink, where the line meets w, at t_k = (w - u)/(v - u). Clamped to [t0, t1]
/// it also covers a line entirely below or above w there, and du_inv = 0 (a constant line) gives
/// a kink at t0. A set that does not fire (w = 0) adds 0.
inline Integral clippedLine(const Interval& iv, const Piece& pc, double w, double t0, double t1) {
  const double tk = std::min(std::max((w - pc.u) * pc.du_inv, t0), t1);
  const double h = iv.q - iv.p;
  const double y0 = iv.p + t0 * h, yk = iv.p + tk * h, y1 = iv.p + t1 * h;
  const double dv = pc.v - pc.u;
  const double g0 = std::min(w, pc.u + t0 * dv), gk = std::min(w, pc.u + tk * dv), g1 = std::min(w, pc.u + t1 * dv);
  return linearIntegral(y0, yk, g0, gk) + linearIntegral(yk, y1, gk, g1);
}

/// One set on the interval (the common case).
inline Integral integrateOne(const Interval& iv, const Piece& pc, double w) {
  return clippedLine(iv, pc, w, 0.0, 1.0);
}

/// sup { t : t * den <= num } for den >= 0, as used below: num / den, or +-inf when den = 0
/// (every t or none).
inline double upTo(double num, double den) {
  if (den > 0.0) return num / den;
  return num >= 0.0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

/// Two sets on the interval where the first, l, is non-increasing and the second, r, non-decreasing:
/// how neighbouring sets of a partition overlap (l's falling edge or plateau, r's rising edge or
/// plateau). Then g_l - g_r is non-increasing, so the max is g_l up to one crossing t_c and g_r
/// after it:  integral = int_0^t_c g_l + int_t_c^1 g_r.
/// t_c = sup { t : g_l(t) >= g_r(t) }, with g_l >= g_r  <=>  w_l >= g_r  and  line_l >= g_r, i.e.
///   (w_l >= w_r  or  line_r(t) <= w_l)  and  (line_l(t) >= w_r  or  line_l(t) >= line_r(t)),
/// each condition holding on an interval [0, t_i] because of the monotonicity.
inline Integral integrateOpposite(const Interval& iv, const Piece& l, double wl, const Piece& r, double wr) {
  const double fall_l = l.u - l.v, rise_r = r.v - r.u;  // both >= 0
  const double t_cap = wl >= wr ? std::numeric_limits<double>::infinity() : upTo(wl - r.u, rise_r);
  const double t_lines = std::max(upTo(l.u - wr, fall_l), upTo(l.u - r.u, fall_l + rise_r));
  const double tc = clampUnit(std::min(t_cap, t_lines));
  return clippedLine(iv, l, wl, 0.0, tc) + clippedLine(iv, r, wr, tc, 1.0);
}

/// Two sets on the interval in any other combination (both rising or both falling; not in a
/// partition, but allowed): max(min(wa, a), min(wb, b)). The clip
/// kinks of a and b cut [0, 1] into three parts on which both clipped sets are linear; on each part
/// their max has at most one more kink, where they cross.
inline Integral integrateTwo(const Interval& iv, const Piece& a, double wa, const Piece& b, double wb) {
  const double ka = clampUnit((wa - a.u) * a.du_inv), kb = clampUnit((wb - b.u) * b.du_inv);
  const double cuts[4] = {0.0, std::min(ka, kb), std::max(ka, kb), 1.0};
  const double h = iv.q - iv.p;
  auto ga = [&](double t) { return std::min(wa, a.u + t * (a.v - a.u)); };
  auto gb = [&](double t) { return std::min(wb, b.u + t * (b.v - b.u)); };
  Integral sum;
  for (int k = 0; k < 3; ++k) {
    const double t0 = cuts[k], t1 = cuts[k + 1];
    const double a0 = ga(t0), a1 = ga(t1), b0 = gb(t0), b1 = gb(t1);
    const double d0 = a0 - b0, d1 = a1 - b1;
    // Crossing at the fraction tau of the part; tau = 1 (no crossing) makes the second piece empty.
    const double tau = (d0 * d1 < 0.0) ? d0 / (d0 - d1) : 1.0;
    const double fc = std::max(a0 + tau * (a1 - a0), b0 + tau * (b1 - b0));
    const double y0 = iv.p + t0 * h, y1 = iv.p + t1 * h, yc = y0 + tau * (y1 - y0);
    sum += linearIntegral(y0, yc, std::max(a0, b0), fc) + linearIntegral(yc, y1, fc, std::max(a1, b1));
  }
  return sum;
}

/// Any number of sets on the interval (only when three or more sets overlap): the clip kinks cut
/// [0, 1] into parts where every clipped set is linear, and on each part the max has kinks where
/// two of them cross.
Integral integrateMax(const Interval& iv, const Piece* all, int count, const double* w) {
  // The pieces of the sets that fire, and their clip kinks inside (0, 1).
  std::array<Piece, kMaxSets> pc;
  std::array<double, kMaxSets + 2> kinks;
  int n = 0, nk = 0;
  kinks[static_cast<size_t>(nk++)] = 0.0;
  for (int i = 0; i < count; ++i) {
    const double wi = w[static_cast<size_t>(all[i].set)];
    if (!(wi > 0.0)) continue;
    pc[static_cast<size_t>(n++)] = all[i];
    const double tk = (wi - all[i].u) * all[i].du_inv;
    if (tk > 0.0 && tk < 1.0) kinks[static_cast<size_t>(nk++)] = tk;
  }
  Integral sum;
  if (n == 0) return sum;
  kinks[static_cast<size_t>(nk++)] = 1.0;
  sortShort(kinks.data(), nk);

  const double h = iv.q - iv.p;
  auto clipped = [&](int i, double t) {
    const Piece& s = pc[static_cast<size_t>(i)];
    return std::min(w[static_cast<size_t>(s.set)], s.u + t * (s.v - s.u));
  };
  std::array<double, kMaxSets> g0, g1;
  std::array<double, kMaxSets * (kMaxSets - 1) / 2 + 2> ts;
  for (int k = 0; k + 1 < nk; ++k) {
    const double s0 = kinks[static_cast<size_t>(k)], s1 = kinks[static_cast<size_t>(k + 1)];
    if (!(s1 > s0)) continue;
    for (int i = 0; i < n; ++i) {
      g0[static_cast<size_t>(i)] = clipped(i, s0);
      g1[static_cast<size_t>(i)] = clipped(i, s1);
    }
    int nt = 0;
    ts[static_cast<size_t>(nt++)] = 0.0;  // tau in [0, 1] across [s0, s1]
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const double d0 = g0[static_cast<size_t>(i)] - g0[static_cast<size_t>(j)];
        const double d1 = g1[static_cast<size_t>(i)] - g1[static_cast<size_t>(j)];
        if ((d0 > 0.0 && d1 < 0.0) || (d0 < 0.0 && d1 > 0.0)) {
          const double tau = d0 / (d0 - d1);
          if (tau > 0.0 && tau < 1.0) ts[static_cast<size_t>(nt++)] = tau;
        }
      }
    ts[static_cast<size_t>(nt++)] = 1.0;
    sortShort(ts.data(), nt);
    auto aggregated = [&](double tau) {
      double f = 0.0;
      for (int i = 0; i < n; ++i)
        f = std::max(f, (1.0 - tau) * g0[static_cast<size_t>(i)] + tau * g1[static_cast<size_t>(i)]);
      return f;
    };
    const double y0 = iv.p + s0 * h, dy = (s1 - s0) * h;
    for (int s = 0; s + 1 < nt; ++s) {
      const double a = ts[static_cast<size_t>(s)], b = ts[static_cast<size_t>(s + 1)];
      if (!(b > a)) continue;
      sum += linearIntegral(y0 + a * dy, y0 + b * dy, aggregated(a), aggregated(b));
    }
  }
  return sum;
}

}  // namespace

CentroidTable::CentroidTable(const MembershipFunction* sets, int n, double lo, double hi) : n_sets_(n) {
  if (n < 0 || n > kMaxSets) throw std::invalid_argument("fuzzy centroid: 0 to kMaxSets sets");
  if (!(lo < hi)) throw std::invalid_argument("fuzzy centroid: need lo < hi");
  // Interval ends: lo, hi and every set vertex strictly inside.
  std::array<double, 2 + 4 * kMaxSets> pts;
  int np = 0;
  pts[static_cast<size_t>(np++)] = lo;
  pts[static_cast<size_t>(np++)] = hi;
  for (int i = 0; i < n; ++i)
    for (double x : {sets[i].a(), sets[i].b(), sets[i].c(), sets[i].d()})
      if (x > lo && x < hi) pts[static_cast<size_t>(np++)] = x;
  std::sort(pts.begin(), pts.begin() + np);
  np = static_cast<int>(std::unique(pts.begin(), pts.begin() + np) - pts.begin());

  for (int k = 0; k + 1 < np; ++k) {
    const double p = pts[static_cast<size_t>(k)], q = pts[static_cast<size_t>(k + 1)];
    Interval iv{p, q, static_cast<int>(pieces_.size()), 0, false};
    // No vertex lies inside (p, q), so each set is on one piece of its trapezoid there; the
    // midpoint tells which.
    const double m = 0.5 * (p + q);
    for (int i = 0; i < n; ++i) {
      const MembershipFunction& f = sets[i];
      Piece pc{i, 1.0, 1.0, 0.0};
      if (m <= f.a() || m >= f.d()) continue;  // 0 on the whole interval
      if (m < f.b()) {                           // rising edge (b > a here)
        pc.u = (p - f.a()) / (f.b() - f.a());
        pc.v = (q - f.a()) / (f.b() - f.a());
      } else if (m > f.c()) {  // falling edge (d > c here)
        pc.u = (f.d() - p) / (f.d() - f.c());
        pc.v = (f.d() - q) / (f.d() - f.c());
      }  // else the plateau: u = v = 1
      if (pc.v != pc.u) pc.du_inv = 1.0 / (pc.v - pc.u);
      pieces_.push_back(pc);
      ++iv.count;
    }
    if (iv.count == 2) {
      // Put a non-increasing piece first and a non-decreasing one second when possible.
      Piece& p0 = pieces_[pieces_.size() - 2];
      Piece& p1 = pieces_[pieces_.size() - 1];
      if (p0.v <= p0.u && p1.v >= p1.u) {
        iv.opposite = true;
      } else if (p1.v <= p1.u && p0.v >= p0.u) {
        std::swap(p0, p1);
        iv.opposite = true;
      }
    }
    if (iv.count > 0) intervals_.push_back(iv);  // intervals where every set is 0 add nothing
  }
}

double CentroidTable::centroid(const double* w_in) const {
  std::array<double, kMaxSets> w;
  for (int i = 0; i < n_sets_; ++i) w[static_cast<size_t>(i)] = w_in[i] > 0.0 ? std::min(w_in[i], 1.0) : 0.0;
  Integral sum;  // twice the area, six times the first moment
  for (const Interval& iv : intervals_) {
    const Piece* pc = &pieces_[static_cast<size_t>(iv.first)];
    if (iv.count == 1)
      sum += integrateOne(iv, pc[0], w[static_cast<size_t>(pc[0].set)]);
    else if (iv.count == 2 && iv.opposite)
      sum += integrateOpposite(iv, pc[0], w[static_cast<size_t>(pc[0].set)], pc[1], w[static_cast<size_t>(pc[1].set)]);
    else if (iv.count == 2)
      sum += integrateTwo(iv, pc[0], w[static_cast<size_t>(pc[0].set)], pc[1], w[static_cast<size_t>(pc[1].set)]);
    else
      sum += integrateMax(iv, pc, iv.count, w.data());
  }
  if (!(sum.area2 > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return sum.moment6 / (3.0 * sum.area2);  // (moment / area) = (moment6 / 6) / (area2 / 2)
}

double clippedCentroid(const MembershipFunction* sets, const double* w, int n, double lo, double hi) {
  return CentroidTable(sets, n, lo, hi).centroid(w);
}

// ---------------------------------------------------------------------------------------------

namespace {

/// N, ZE, P triangles on [lo, hi] with ZE peaking at 0 (a partition of unity when lo < 0 < hi).
Variable threeSetVariable(const std::string& name, double lo, double hi) {
  Variable v(name, lo, hi);
  v.addSet("N", MembershipFunction::triangle(lo, lo, 0.0));
  v.addSet("ZE", MembershipFunction::triangle(lo, 0.0, hi));
  v.addSet("P", MembershipFunction::triangle(0.0, hi, hi));
  return v;
}

/// NB NS ZE PS PB: five evenly spaced triangles on [lo, hi], shoulders at the bounds.
Variable fiveSetVariable(const std::string& name, double lo, double hi) {
  Variable v(name, lo, hi);
  const double s = (hi - lo) / 4.0;
  const char* names[5] = {"NB", "NS", "ZE", "PS", "PB"};
  for (int i = 0; i < 5; ++i) {
    const double peak = lo + i * s;
    v.addSet(names[i], MembershipFunction::triangle(i == 0 ? lo : peak - s, peak, i == 4 ? hi : peak + s));
  }
  return v;
}

void requirePositive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string("fuzzy system: ") + what + " must be > 0");
}

}  // namespace

MamdaniSystem makeFakfBetaSystem(const BetaSystemConfig& cfg) {
  requirePositive(cfg.e_range, "e_range");
  requirePositive(cfg.dp_range, "dp_range");
  if (!(cfg.beta_min > 0.0 && cfg.beta_min < 1.0 && cfg.beta_max > 1.0 && std::isfinite(cfg.beta_max)))
    throw std::invalid_argument("fuzzy beta system: need 0 < beta_min < 1 < beta_max");
  const double L = 1.0 - cfg.beta_min, U = cfg.beta_max - 1.0, m = std::min(L, U);
  Variable beta("beta", cfg.beta_min, cfg.beta_max);
  beta.addSet("PS", MembershipFunction::trapezoid(cfg.beta_min, cfg.beta_min, 1.0 - 0.75 * L, 1.0 - 0.25 * L));
  beta.addSet("PM", MembershipFunction::trapezoid(1.0 - 0.5 * m, 1.0 - 0.1 * m, 1.0 + 0.1 * m, 1.0 + 0.5 * m));
  beta.addSet("PB", MembershipFunction::trapezoid(1.0 + 0.25 * U, 1.0 + 0.75 * U, cfg.beta_max, cfg.beta_max));
  MamdaniSystem sys({threeSetVariable("E'", -cfg.e_range, cfg.e_range),
                     threeSetVariable("dP'", -cfg.dp_range, cfg.dp_range)},
                    beta);
  sys.addRule({"N", "N"}, "PS");
  sys.addRule({"N", "ZE"}, "PS");
  sys.addRule({"N", "P"}, "PM");
  sys.addRule({"ZE", "N"}, "PS");
  sys.addRule({"ZE", "ZE"}, "PM");
  sys.addRule({"ZE", "P"}, "PB");
  sys.addRule({"P", "N"}, "PM");
  sys.addRule({"P", "ZE"}, "PB");
  sys.addRule({"P", "P"}, "PB");
  sys.setFallback(1.0);
  return sys;
}

MamdaniSystem makeFakfGammaSystem(const GammaSystemConfig& cfg) {
  if (!(cfg.de_min < cfg.de_max) || !(cfg.gamma_min < cfg.gamma_max) || !(cfg.gamma_min >= 1.0))
    throw std::invalid_argument("fuzzy gamma system: need de_min < de_max and 1 <= gamma_min < gamma_max");
  MamdaniSystem sys({fiveSetVariable("dE", cfg.de_min, cfg.de_max)}, fiveSetVariable("gamma", cfg.gamma_min, cfg.gamma_max));
  for (const char* s : {"NB", "NS", "ZE", "PS", "PB"}) sys.addRule({std::string(s)}, s);
  return sys;
}

MamdaniSystem makeFakfDomSystem(const DomSystemConfig& cfg) {
  requirePositive(cfg.dom_range, "dom_range");
  requirePositive(cfg.dr_max, "dr_max");
  MamdaniSystem sys({threeSetVariable("DoM", -cfg.dom_range, cfg.dom_range)},
                    threeSetVariable("dR", -cfg.dr_max, cfg.dr_max));
  sys.addRule({"N"}, "N");
  sys.addRule({"ZE"}, "ZE");
  sys.addRule({"P"}, "P");
  sys.setFallback(0.0);
  return sys;
}

}  // namespace fuzzy
}  // namespace predvs
