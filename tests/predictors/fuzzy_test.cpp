// Tests of the Mamdani fuzzy system and the three ready-made systems of the fuzzy adaptive
// Kalman filters (docs/MODELS.md §3).
#include "predvs/predictors/fuzzy.h"

#include <gtest/gtest.h>

#include <random>

namespace predvs {
namespace fuzzy {
namespace {

// The centroid is computed in closed form: only rounding separates it from exact arithmetic.
constexpr double kExactTol = 1e-12;
// Brute-force midpoint integration on 200000 cells has an error of order (width/200000)^2 per kink,
// well below this.
constexpr double kGridTol = 1e-6;

TEST(MembershipFunction, TriangleTrapezoidAndShoulders) {
  // GIVEN a triangle, a trapezoid and a left shoulder
  const auto tri = MembershipFunction::triangle(-0.5, 0.0, 0.5);
  const auto trap = MembershipFunction::trapezoid(0.9, 0.98, 1.02, 1.1);
  const auto left = MembershipFunction::triangle(-0.5, -0.5, 0.0);
  // THEN their values are the hand-computed ones
  EXPECT_NEAR(tri(0.0), 1.0, kExactTol);
  EXPECT_NEAR(tri(0.25), 0.5, kExactTol);
  EXPECT_NEAR(tri(-0.4), 0.2, kExactTol);
  EXPECT_EQ(tri(0.6), 0.0);
  EXPECT_NEAR(trap(0.94), 0.5, kExactTol);
  EXPECT_EQ(trap(1.0), 1.0);
  EXPECT_NEAR(trap(1.08), 0.25, kExactTol);
  EXPECT_EQ(left(-0.5), 1.0);  // vertical edge: full membership at the bound
  EXPECT_NEAR(left(-0.1), 0.2, kExactTol);
  EXPECT_EQ(left(0.1), 0.0);
  EXPECT_THROW(MembershipFunction::trapezoid(1.0, 0.0, 2.0, 3.0), std::invalid_argument);
}

TEST(Variable, ClampsInputsToTheUniverse) {
  Variable v("E'", -0.5, 0.5);
  const int n = v.addSet("N", MembershipFunction::triangle(-0.5, -0.5, 0.0));
  EXPECT_EQ(v.clamp(-3.0), -0.5);
  EXPECT_EQ(v.clamp(0.7), 0.5);
  EXPECT_EQ(v.membership(n, -3.0), 1.0);  // far outside counts as the bound
  EXPECT_EQ(v.indexOf("N"), n);
  EXPECT_THROW(v.indexOf("PB"), std::invalid_argument);
}

TEST(BetaSystem, RuleFiringAtOneQuarter) {
  // GIVEN the improved-FAKF beta system, E' = 0.25 and dP' = 0
  const MamdaniSystem sys = makeFakfBetaSystem();
  const double x[2] = {0.25, 0.0};
  // WHEN the rules fire
  const auto w = sys.activation(x);
  // THEN E' is ZE 0.5 and P 0.5, dP' is ZE 1: (ZE,ZE)->PM and (P,ZE)->PB fire at 0.5, nothing else
  EXPECT_EQ(w[static_cast<size_t>(sys.output().indexOf("PS"))], 0.0);
  EXPECT_NEAR(w[static_cast<size_t>(sys.output().indexOf("PM"))], 0.5, kExactTol);
  EXPECT_NEAR(w[static_cast<size_t>(sys.output().indexOf("PB"))], 0.5, kExactTol);
}

TEST(BetaSystem, TwoRuleCentroidComputedByHand) {
  // GIVEN E' = 0.25, dP' = 0: PM = (0.9, 0.98, 1.02, 1.1) and PB = (1.05, 1.15, 1.2, 1.2), each
  // clipped at 0.5 (previous test). The aggregated set max(PM', PB') is, piece by piece:
  //   [0.9, 0.94]    rises 0 -> 0.5            (PM edge reaches 0.5 at 0.9 + 0.5*0.08)
  //   [0.94, 1.06]   flat 0.5                   (PM falls from 0.5 at 1.1 - 0.5*0.08)
  //   [1.06, xc]     PM falling 0.5 -> fc       xc where (1.1-x)/0.08 = (x-1.05)/0.1: xc = 97/90
  //   [xc, 1.10]     PB rising fc -> 0.5        fc = (1.1 - xc)/0.08 = 5/18
  //   [1.10, 1.2]    flat 0.5
  // A linear piece f0 -> f1 on [x0, x1] has area (f0+f1)/2 dx and moment dx (x0(2f0+f1) + x1(f0+2f1))/6.
  // Summing: area = 61/450, moment = 2791/19440, centroid = 13955/13176 = 1.05912264723740...
  const MamdaniSystem sys = makeFakfBetaSystem();
  // WHEN the system is evaluated
  const double beta = sys.evaluate({0.25, 0.0});
  // THEN it equals the hand-computed centroid
  EXPECT_NEAR(beta, 13955.0 / 13176.0, kExactTol);
}

TEST(DomSystem, TwoRuleCentroidComputedByHand) {
  // GIVEN the classic DoM system (DoM in [-10, 10], dR in [-0.5, 0.5]) and DoM = 5: ZE 0.5, P 0.5.
  // ZE = (-0.5, 0, 0.5) and P = (0, 0.5, 0.5) clipped at 0.5 aggregate to the trapezoid
  // (-0.5, -0.25, 0.5, 0.5) of height 0.5. Per unit height: area 0.125 + 0.75 = 7/8; moment
  // 0.125 * (-0.5 + 2/3 * 0.25) + (0.5^2 - 0.25^2)/2 = -1/24 + 3/32 = 5/96; centroid = 5/84.
  const MamdaniSystem sys = makeFakfDomSystem();
  // WHEN evaluated at DoM = 5 and at DoM = -5
  // THEN dR = 5/84 and, by the odd symmetry of sets and rules, -5/84
  EXPECT_NEAR(sys.evaluate(5.0), 5.0 / 84.0, kExactTol);
  EXPECT_NEAR(sys.evaluate(-5.0), -5.0 / 84.0, kExactTol);
  EXPECT_NEAR(sys.evaluate(0.0), 0.0, kExactTol);
  // and a full P (clamped input) gives the centroid of the shoulder triangle, 2/3 * 0.5
  EXPECT_NEAR(sys.evaluate(100.0), 1.0 / 3.0, kExactTol);
}

TEST(BetaSystem, KeepsRAtZeroAndFollowsTheSignOfTheMismatch) {
  const MamdaniSystem sys = makeFakfBetaSystem();
  // GIVEN matched innovations THEN beta is exactly 1 (only PM fires, and PM is symmetric about 1)
  EXPECT_NEAR(sys.evaluate({0.0, 0.0}), 1.0, kExactTol);
  // GIVEN a grid of positive (negative) inputs THEN beta > 1 (< 1), inside [0.8, 1.2],
  // and beta(-E', -dP') = 2 - beta(E', dP') (mirror-symmetric sets and rule table)
  for (int i = 1; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) {
      const double e = 0.06 * i, dp = 1.2 * j;  // e up to 0.6, dp up to 12: past the universe too
      const double up = sys.evaluate({e, dp}), down = sys.evaluate({-e, -dp});
      EXPECT_GT(up, 1.0) << "E'=" << e << " dP'=" << dp;
      EXPECT_LT(down, 1.0) << "E'=" << -e << " dP'=" << -dp;
      EXPECT_LE(up, 1.2);
      EXPECT_GE(down, 0.8);
      EXPECT_NEAR(up - 1.0, 1.0 - down, kExactTol);
      const double up_dp_only = sys.evaluate({0.0, 1.2 * i});
      EXPECT_GT(up_dp_only, 1.0);
    }
  }
}

TEST(GammaSystem, MonotoneOverTheUniverse) {
  // GIVEN the P-inflation map dE in [2, 50] -> gamma in [100, 1000]
  const MamdaniSystem sys = makeFakfGammaSystem();
  // THEN at the ends only NB (PB) fires: centroid of the shoulder triangle (100, 100, 325) = 175,
  // of (775, 1000, 1000) = 925, and at the middle dE = 26 only ZE fires: 550
  EXPECT_NEAR(sys.evaluate(2.0), 175.0, 1e-9);
  EXPECT_NEAR(sys.evaluate(0.0), 175.0, 1e-9);  // clamped
  EXPECT_NEAR(sys.evaluate(26.0), 550.0, 1e-9);
  EXPECT_NEAR(sys.evaluate(50.0), 925.0, 1e-9);
  // and gamma is non-decreasing in dE, strictly increasing inside the universe
  double prev = sys.evaluate(1.0);
  for (double de = 1.1; de <= 55.0; de += 0.1) {
    const double g = sys.evaluate(de);
    if (de > 2.05 && de < 49.95)
      EXPECT_GT(g, prev) << "dE=" << de;
    else
      EXPECT_GE(g, prev - 1e-9) << "dE=" << de;
    prev = g;
  }
}

// Brute-force centroid on a fine midpoint grid: an independent check of the analytic one.
double gridCentroid(const std::vector<MembershipFunction>& sets, const std::vector<double>& w, double lo, double hi) {
  const int n = 200000;
  const double h = (hi - lo) / n;
  double area = 0.0, moment = 0.0;
  for (int k = 0; k < n; ++k) {
    const double y = lo + (k + 0.5) * h;
    double f = 0.0;
    for (size_t i = 0; i < sets.size(); ++i) f = std::max(f, std::min(w[i], sets[i](y)));
    area += f;
    moment += f * y;
  }
  return moment / area;
}

TEST(ClippedCentroid, MatchesBruteForceOnRandomSets) {
  // GIVEN random overlapping trapezoids and clip levels (seeded)
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<MembershipFunction> sets;
    std::vector<double> w;
    const int n = 2 + trial % 4;
    for (int i = 0; i < n; ++i) {
      double p[4] = {u(rng) * 10, u(rng) * 10, u(rng) * 10, u(rng) * 10};
      std::sort(p, p + 4);
      if (trial % 3 == 0) p[1] = p[2];  // some triangles
      sets.push_back(MembershipFunction::trapezoid(p[0], p[1], p[2], p[3] + 0.1));
      w.push_back(trial % 5 == 0 && i == 0 ? 0.0 : u(rng));
    }
    // WHEN the analytic centroid is computed
    const double analytic = clippedCentroid(sets.data(), w.data(), n, 0.0, 10.1);
    // THEN it matches the brute-force integral
    EXPECT_NEAR(analytic, gridCentroid(sets, w, 0.0, 10.1), kGridTol * 10.0) << "trial " << trial;
  }
}

TEST(MamdaniSystem, RejectsBadRulesAndReturnsFallbackWhenNothingFires) {
  Variable in("x", 0.0, 1.0);
  in.addSet("low", MembershipFunction::triangle(0.0, 0.0, 0.3));
  Variable out("y", 0.0, 2.0);
  out.addSet("a", MembershipFunction::triangle(0.0, 1.0, 2.0));
  MamdaniSystem sys({in}, out);
  EXPECT_THROW(sys.addRule({"high"}, "a"), std::invalid_argument);
  EXPECT_THROW(sys.addRule(std::vector<int>{0, 0}, 0), std::invalid_argument);
  sys.addRule({"low"}, "a");
  // GIVEN an input outside every set THEN no rule fires and the fallback (mid-universe) is returned
  EXPECT_EQ(sys.evaluate(0.9), 1.0);
  EXPECT_NEAR(sys.evaluate(0.0), 1.0, kExactTol);  // symmetric triangle: centroid at its peak
}

}  // namespace
}  // namespace fuzzy
}  // namespace predvs
