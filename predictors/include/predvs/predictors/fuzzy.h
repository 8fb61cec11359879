// predvs — a small Mamdani fuzzy inference system and the three systems the fuzzy adaptive
// Kalman filters use (docs/MODELS.md §3, paper 000 §4).
//
// Inference (Mamdani, max-min):
//   * every input is clamped to its universe [lo, hi] and fuzzified by its membership functions;
//   * a rule "IF x1 is A1 AND x2 is A2 ... THEN y is B" fires with strength w = min_i mu_Ai(x_i);
//   * each output set B is clipped at the largest strength of the rules that conclude B, and the
//     clipped sets are aggregated by max: mu(y) = max_B min(w_B, mu_B(y));
//   * the crisp output is the centroid y* = int y mu(y) dy / int mu(y) dy over the output universe.
//
// Centroid: computed analytically, not on a sampled grid. Clipped triangles and trapezoids are
// piecewise linear, so their max is piecewise linear with breakpoints at the set vertices, at the
// points where an edge meets its clip level, and where two clipped sets cross. Between consecutive
// breakpoints both integrals are exact closed forms, so the result has no grid error (tests can
// compare against hand-computed values to 1e-12).
//
// Cost: the filters call evaluate() once per channel per frame, so it is on the hot path. The
// vertices of the output sets do not change, so a system splits its output universe once, at
// construction, into the intervals between consecutive vertices and records which sets are
// non-zero on each and their (linear) memberships there (CentroidTable). An evaluation then walks
// those intervals and only has to place the clip points and crossings of the few sets present on
// each one: one set (one clip kink), or two neighbours of opposite slopes (a single crossing, found
// in closed form); more only for unusual set layouts. No sorting, no heap allocation, no
// data-dependent branch on the usual paths. Measured (Release, this machine): the 3-set beta
// system ~140 ns per evaluation, the dR system ~70 ns (520 and 270 ns with the previous
// implementation, which sorted all breakpoints at every call).
#pragma once

#include <array>
#include <initializer_list>
#include <string>
#include <vector>

namespace predvs {
namespace fuzzy {

/// Largest number of sets on one variable and of inputs of one system (fixed so that evaluate()
/// works on the stack; the systems here use at most 5 sets and 2 inputs).
constexpr int kMaxSets = 8;
constexpr int kMaxInputs = 4;

/// Trapezoidal membership function with feet a <= b <= c <= d:
///   mu(x) = 0 for x < a or x > d, (x - a)/(b - a) on [a, b), 1 on [b, c], (d - x)/(d - c) on (c, d].
/// A triangle is the case b == c. A vertical edge (a == b or c == d) makes a shoulder: mu = 1 at
/// that edge, which is how the outermost sets of a universe reach full membership at its bounds.
class MembershipFunction {
 public:
  MembershipFunction() = default;
  /// Trapezoid (a, b, c, d); throws std::invalid_argument unless a <= b <= c <= d and a < d.
  static MembershipFunction trapezoid(double a, double b, double c, double d);
  /// Triangle with feet a, c and peak b: trapezoid(a, b, b, c).
  static MembershipFunction triangle(double a, double b, double c);

  double operator()(double x) const {
    if (x < a_ || x > d_) return 0.0;
    if (x < b_) return (x - a_) / (b_ - a_);  // x < b implies b > a
    if (x <= c_) return 1.0;
    return (d_ - x) / (d_ - c_);  // c < x <= d implies d > c
  }
  double a() const { return a_; }
  double b() const { return b_; }
  double c() const { return c_; }
  double d() const { return d_; }

 private:
  MembershipFunction(double a, double b, double c, double d) : a_(a), b_(b), c_(c), d_(d) {}
  double a_ = 0.0, b_ = 0.0, c_ = 0.0, d_ = 1.0;
};

/// A linguistic variable: a universe [lo, hi] and named fuzzy sets on it.
class Variable {
 public:
  /// Throws std::invalid_argument unless lo < hi.
  Variable(std::string name, double lo, double hi);
  /// Adds a set and returns its index (0, 1, ...). Throws if more than kMaxSets sets.
  int addSet(const std::string& name, const MembershipFunction& mf);

  const std::string& name() const { return name_; }
  double lo() const { return lo_; }
  double hi() const { return hi_; }
  int size() const { return static_cast<int>(sets_.size()); }
  const MembershipFunction& set(int i) const { return sets_.at(static_cast<size_t>(i)); }
  const std::string& setName(int i) const { return set_names_.at(static_cast<size_t>(i)); }
  /// Index of the set called `name`; throws std::invalid_argument if there is none.
  int indexOf(const std::string& name) const;
  /// x limited to [lo, hi] (inputs outside the universe count as its nearest bound).
  double clamp(double x) const;
  /// Membership of clamp(x) in set i.
  double membership(int i, double x) const { return set(i)(clamp(x)); }

 private:
  std::string name_;
  double lo_, hi_;
  std::vector<MembershipFunction> sets_;
  std::vector<std::string> set_names_;
};

/// The output universe [lo, hi] of a fixed list of sets, cut once into the intervals between
/// consecutive set vertices, for fast exact centroids of max_i min(w_i, mu_i(y)) for any levels w.
///
/// On each interval (p, q) every set is 0, or linear: mu_i = u_i at p+ and v_i at q- (one-sided
/// limits, so a vertical shoulder at p or q is taken from inside the interval). With t = (y - p)/(q - p),
/// a clipped set is min(w_i, u_i + t (v_i - u_i)), with one kink where the line meets w_i, and the
/// max over the sets present has further kinks where two clipped sets cross. centroid() integrates
/// that max exactly between the kinks: for a linear f from f0 at x0 to f1 at x1,
///   area += (f0 + f1) dx / 2,   moment += dx (x0 (2 f0 + f1) + x1 (f0 + 2 f1)) / 6,   dx = x1 - x0,
/// and returns moment / area. Built from the same sets, it gives the same result as integrating
/// over all breakpoints at once, to rounding.
class CentroidTable {
 public:
  /// Membership of one set on one interval: u at p+, v at q-; du_inv = 1/(v - u), 0 when u == v.
  struct Piece {
    int set;
    double u, v, du_inv;
  };
  /// One interval [p, q] and the sets that are non-zero on it: pieces()[first .. first + count).
  /// `opposite`: two sets, the first non-increasing and the second non-decreasing on [p, q] (how
  /// neighbours in a partition overlap); their max then has a single crossing.
  struct Interval {
    double p, q;
    int first, count;
    bool opposite;
  };

  CentroidTable() = default;
  /// Throws std::invalid_argument if n > kMaxSets or not lo < hi.
  CentroidTable(const MembershipFunction* sets, int n, double lo, double hi);
  /// Centroid for clip levels w[0 .. n-1] (clamped to [0, 1], NaN as 0); NaN when the area is 0.
  /// No allocation; the cost grows with the number of intervals and of sets present on each.
  double centroid(const double* w) const;

  /// Intervals of [lo, hi] where at least one set is non-zero, in increasing order (tests).
  const std::vector<Interval>& intervals() const { return intervals_; }
  const std::vector<Piece>& pieces() const { return pieces_; }

 private:
  int n_sets_ = 0;
  std::vector<Interval> intervals_;
  std::vector<Piece> pieces_;
};

/// Mamdani system with n inputs and one output.
class MamdaniSystem {
 public:
  /// Index meaning "this input does not take part in the rule".
  static constexpr int kAny = -1;

  /// Throws std::invalid_argument if there are no inputs, more than kMaxInputs, or a variable
  /// without sets.
  MamdaniSystem(std::vector<Variable> inputs, Variable output);

  /// Adds "IF input_0 is antecedent[0] AND ... THEN output is consequent" (set indices; kAny
  /// skips an input). Throws on a wrong count or an index out of range.
  void addRule(const std::vector<int>& antecedent, int consequent);
  /// Same with set names, e.g. addRule({"N", "ZE"}, "PS"); "*" skips an input.
  void addRule(const std::vector<std::string>& antecedent, const std::string& consequent);

  int inputs() const { return static_cast<int>(inputs_.size()); }
  const Variable& input(int i) const { return inputs_.at(static_cast<size_t>(i)); }
  const Variable& output() const { return output_; }
  int rules() const { return static_cast<int>(rules_.size()); }

  /// Clip level of every output set for the given (unclamped) inputs: the max over the rules that
  /// conclude that set of the min of their antecedent memberships. Size output().size().
  std::array<double, kMaxSets> activation(const double* x) const;
  /// Crisp output: analytic centroid of the aggregated output set (see the file comment).
  /// When no rule fires (zero area) returns `fallback()`.
  double evaluate(const double* x) const;
  double evaluate(std::initializer_list<double> x) const;
  double evaluate(double x0) const { return evaluate(&x0); }

  /// Output when no rule fires; default the middle of the output universe.
  double fallback() const { return fallback_; }
  void setFallback(double y) { fallback_ = y; }

 private:
  struct Rule {
    std::array<int, kMaxInputs> antecedent;
    int consequent;
  };
  /// Universe and sets of an input in fixed-size storage, for activation(). The variables cannot
  /// change once they are in the system (only const access), so the copies made by the
  /// constructor, like the centroid table, stay valid.
  struct FlatInput {
    double lo = 0.0, hi = 1.0;
    int n_sets = 0;
    std::array<MembershipFunction, kMaxSets> sets{};
  };

  std::vector<Variable> inputs_;
  Variable output_;
  std::vector<Rule> rules_;
  double fallback_;
  int n_inputs_ = 0;
  std::array<FlatInput, kMaxInputs> flat_inputs_{};
  CentroidTable centroid_;  ///< the output universe, cut at the vertices of its sets
};

/// Analytic centroid of max_i min(w_i, mu_i(y)) over [lo, hi]; `n` sets, `w` their clip levels
/// (clamped to [0, 1]; NaN counts as 0). Returns NaN when the aggregated area is zero. Builds a
/// CentroidTable for the call (so it allocates); a MamdaniSystem keeps its table instead.
/// Exposed for tests and reuse.
double clippedCentroid(const MembershipFunction* sets, const double* w, int n, double lo, double hi);

// ---------------------------------------------------------------------------------------------
// The ready-made systems of docs/MODELS.md §3.

/// Universes of the improved-FAKF R adaptation (paper 000 §4.1; defaults are the paper's ranges).
struct BetaSystemConfig {
  double e_range = 0.5;    ///< E' universe [-e_range, e_range] (px)
  double dp_range = 10.0;  ///< dP' universe [-dp_range, dp_range] (px^2)
  double beta_min = 0.8;   ///< output universe [beta_min, beta_max], beta_min < 1 < beta_max
  double beta_max = 1.2;
};

/// beta = f(E', dP'), used as R(k) = beta R(k-1).
/// Inputs: triangular N = (lo, lo, 0), ZE = (lo, 0, hi), P = (0, hi, hi) (a partition of unity).
/// Output (trapezoids, choice: the paper's Fig. 3 is lost), with m = min(1 - beta_min, beta_max - 1)
/// so that PM is symmetric about 1.0 whatever the range, hence beta = 1 exactly at E' = dP' = 0:
///   PS = (beta_min, beta_min, 1 - 0.75 L, 1 - 0.25 L),  L = 1 - beta_min
///   PM = (1 - 0.5 m, 1 - 0.1 m, 1 + 0.1 m, 1 + 0.5 m)
///   PB = (1 + 0.25 U, 1 + 0.75 U, beta_max, beta_max),  U = beta_max - 1
/// With the defaults: PS (0.8,0.8,0.85,0.95), PM (0.9,0.98,1.02,1.1), PB (1.05,1.15,1.2,1.2); the
/// centroid keeps beta within about [0.854, 1.146].
/// Rules (docs/MODELS.md §3; E' rows, dP' columns N ZE P): N: PS PS PM; ZE: PS PM PB; P: PM PB PB.
/// Input 0 is E', input 1 is dP'. Throws std::invalid_argument on a bad configuration.
MamdaniSystem makeFakfBetaSystem(const BetaSystemConfig& config = {});

/// Universes of the improved-FAKF P inflation (paper 000 §4.2; defaults are the paper's ranges).
struct GammaSystemConfig {
  double de_min = 2.0;  ///< dE universe [de_min, de_max] (px)
  double de_max = 50.0;
  double gamma_min = 100.0;  ///< output universe [gamma_min, gamma_max]
  double gamma_max = 1000.0;
};

/// gamma = f(dE): five evenly spaced triangles NB NS ZE PS PB on each universe (outer ones are
/// shoulders at the bounds; the paper's Fig. 4 is lost, "the same sets as the input" is read as the
/// same shapes), rules NB->NB, NS->NS, ZE->ZE, PS->PS, PB->PB. The output is monotone
/// non-decreasing in dE; with the defaults it runs from 175 (dE <= 2) to 925 (dE >= 50).
MamdaniSystem makeFakfGammaSystem(const GammaSystemConfig& config = {});

/// Universes of the classic (Escamilla-Ambrosio & Mort) FAKF.
struct DomSystemConfig {
  double dom_range = 10.0;  ///< DoM universe [-dom_range, dom_range] (px^2), as dP' of the improved filter
  double dr_max = 0.5;      ///< output dR universe [-dr_max, dr_max] (px^2 per frame)
};

/// dR = f(DoM), DoM = C - S (docs/MODELS.md §3 sign: actual minus theoretical), used as R(k) = R(k-1) + dR.
/// Input and output: triangles N = (lo, lo, 0), ZE = (lo, 0, hi), P = (0, hi, hi); rules
/// N -> N (decrease R), ZE -> ZE (keep), P -> P (increase R). Odd-symmetric, dR(0) = 0 exactly,
/// |dR| <= 2/3 dr_max (centroid of a full shoulder triangle).
MamdaniSystem makeFakfDomSystem(const DomSystemConfig& config = {});

}  // namespace fuzzy
}  // namespace predvs
