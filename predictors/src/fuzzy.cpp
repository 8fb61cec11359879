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

double MembershipFunction::operator()(double x) const {
  if (x < a_ || x > d_) return 0.0;
  if (x < b_) return (x - a_) / (b_ - a_);  // x < b implies b > a
  if (x <= c_) return 1.0;
  return (d_ - x) / (d_ - c_);  // c < x <= d implies d > c
}

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
  std::array<std::array<double, kMaxSets>, kMaxInputs> mu{};
  for (int i = 0; i < inputs(); ++i) {
    const Variable& v = inputs_[static_cast<size_t>(i)];
    const double xi = v.clamp(x[i]);
    for (int s = 0; s < v.size(); ++s) mu[static_cast<size_t>(i)][static_cast<size_t>(s)] = v.set(s)(xi);
  }
  std::array<double, kMaxSets> w{};
  for (const Rule& r : rules_) {
    double strength = 1.0;  // AND = min
    for (int i = 0; i < inputs(); ++i) {
      const int a = r.antecedent[static_cast<size_t>(i)];
      if (a != kAny) strength = std::min(strength, mu[static_cast<size_t>(i)][static_cast<size_t>(a)]);
    }
    double& wc = w[static_cast<size_t>(r.consequent)];
    wc = std::max(wc, strength);  // aggregation = max
  }
  return w;
}

double MamdaniSystem::evaluate(const double* x) const {
  const std::array<double, kMaxSets> w = activation(x);
  std::array<MembershipFunction, kMaxSets> sets;
  for (int s = 0; s < output_.size(); ++s) sets[static_cast<size_t>(s)] = output_.set(s);
  const double y = clippedCentroid(sets.data(), w.data(), output_.size(), output_.lo(), output_.hi());
  return std::isfinite(y) ? y : fallback_;
}

double MamdaniSystem::evaluate(std::initializer_list<double> x) const {
  if (static_cast<int>(x.size()) != inputs())
    throw std::invalid_argument("fuzzy system: expected " + std::to_string(inputs()) + " inputs");
  return evaluate(x.begin());
}

double clippedCentroid(const MembershipFunction* all_sets, const double* all_w, int n_sets, double lo, double hi) {
  if (n_sets > kMaxSets) throw std::invalid_argument("fuzzy centroid: more than kMaxSets sets");
  // Only the sets that fire take part (a zero clip level contributes nothing to the max).
  std::array<MembershipFunction, kMaxSets> sets;
  std::array<double, kMaxSets> w{};
  int n = 0;
  for (int i = 0; i < n_sets; ++i) {
    const double wi = std::min(std::max(all_w[i], 0.0), 1.0);
    if (!(wi > 0.0)) continue;
    sets[static_cast<size_t>(n)] = all_sets[i];
    w[static_cast<size_t>(n)] = wi;
    ++n;
  }
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  // Breakpoints of every clipped set inside [lo, hi]: its feet and shoulders and the points where
  // its edges meet the clip level.
  std::array<double, 2 + 6 * kMaxSets> pts{};
  int np = 0;
  pts[static_cast<size_t>(np++)] = lo;
  pts[static_cast<size_t>(np++)] = hi;
  for (int i = 0; i < n; ++i) {
    const double wi = w[static_cast<size_t>(i)];
    const MembershipFunction& m = sets[static_cast<size_t>(i)];
    const double cand[6] = {m.a(), m.b(), m.c(), m.d(), m.a() + wi * (m.b() - m.a()), m.d() - wi * (m.d() - m.c())};
    for (double p : cand)
      if (p > lo && p < hi) pts[static_cast<size_t>(np++)] = p;
  }
  std::sort(pts.begin(), pts.begin() + np);
  np = static_cast<int>(std::unique(pts.begin(), pts.begin() + np) - pts.begin());

  auto clipped = [&](int i, double y) {
    return std::min(w[static_cast<size_t>(i)], sets[static_cast<size_t>(i)](y));
  };

  double area = 0.0, moment = 0.0;
  std::array<double, kMaxSets> gp{}, gq{};
  std::array<double, kMaxSets * (kMaxSets - 1) / 2 + 2> ts{};
  for (int k = 0; k + 1 < np; ++k) {
    const double p = pts[static_cast<size_t>(k)], q = pts[static_cast<size_t>(k + 1)], h = q - p;
    if (!(h > 0.0)) continue;
    // Each clipped set is linear on the open interval (p, q). Its one-sided limits at p and q come
    // from two interior samples, which stays exact at discontinuities (vertical shoulders).
    for (int i = 0; i < n; ++i) {
      const double g1 = clipped(i, p + 0.25 * h), g2 = clipped(i, p + 0.75 * h);
      gp[static_cast<size_t>(i)] = 1.5 * g1 - 0.5 * g2;
      gq[static_cast<size_t>(i)] = 1.5 * g2 - 0.5 * g1;
    }
    // The max of linear functions is piecewise linear, with kinks where two of them cross.
    int nt = 0;
    ts[static_cast<size_t>(nt++)] = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const double dp = gp[static_cast<size_t>(i)] - gp[static_cast<size_t>(j)];
        const double dq = gq[static_cast<size_t>(i)] - gq[static_cast<size_t>(j)];
        if ((dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0)) {
          const double t = dp / (dp - dq);
          if (t > 0.0 && t < 1.0) ts[static_cast<size_t>(nt++)] = t;
        }
      }
    ts[static_cast<size_t>(nt++)] = 1.0;
    std::sort(ts.begin(), ts.begin() + nt);
    auto aggregated = [&](double t) {
      double f = 0.0;
      for (int i = 0; i < n; ++i)
        f = std::max(f, (1.0 - t) * gp[static_cast<size_t>(i)] + t * gq[static_cast<size_t>(i)]);
      return f;
    };
    for (int s = 0; s + 1 < nt; ++s) {
      const double t0 = ts[static_cast<size_t>(s)], t1 = ts[static_cast<size_t>(s + 1)];
      if (!(t1 > t0)) continue;
      const double x0 = p + t0 * h, x1 = p + t1 * h, dx = x1 - x0;
      const double f0 = aggregated(t0), f1 = aggregated(t1);
      // Exact integrals of a linear f over [x0, x1].
      area += 0.5 * (f0 + f1) * dx;
      moment += dx * (x0 * (2.0 * f0 + f1) + x1 * (f0 + 2.0 * f1)) / 6.0;
    }
  }
  if (!(area > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return moment / area;
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
