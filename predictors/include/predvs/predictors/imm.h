// predvs — interacting multiple model (IMM) predictor: constant position + constant velocity +
// constant acceleration (or Singer) modes.
//
// docs/MODELS.md §14. Not in any of the five papers: the standard estimator for targets that switch
// between regimes (Blom & Bar-Shalom 1988; Bar-Shalom, Li, Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 2001, §11.6). Each channel runs one Kalman filter per
// mode on the common state x = [p, v, a] (px, px/s, px/s^2), H = [1, 0, 0]; a mode of dimension d
// has the first d states, its F and Q zero the others:
//   CP (d = 1): p' = p,  Q = q_cp T                    (random walk, q_cp px^2/s: a target at rest)
//   CV (d = 2): F = [[1, T], [0, 1]],  Q = cvProcessNoise(q_cv, T)   (kf-cv's model, q_cv px^2/s^3)
//   CA (d = 3): F = caTransition(T),   Q = caProcessNoise(q_ca, T)   (kf-ca's model, q_ca px^2/s^5);
//               with alpha > 0 the Singer model instead (cs_akf.h: singerTransition(alpha, T),
//               singerProcessNoise(alpha, q_ca / (2 alpha), T))
// The defaults of q_cv and q_ca are kf-cv's and kf-ca's (kalman_baselines.h), r is estimated as
// theirs (noise_estimate.h): the CV and CA modes ARE the two single models imm is compared with.
//
// Mode chain, stated per second so that it is the same at any frame period T: a rate matrix
// Lambda with Lambda_ii = -1 / tau_i (mean sojourn time tau_i in s) and Lambda_ij = 1 / (tau_i (M - 1))
// (a mode is left for each other mode alike), and p_ij(T) = [exp(Lambda T)]_ij (chain(), scaling and
// squaring). Its stationary shares are proportional to the tau_i.
//
// One cycle over T, per channel (mu_i: mode probabilities after the last update):
//   mixing        c_j = sum_i p_ij mu_i,  mu_i|j = p_ij mu_i / c_j,
//                 x0_j = sum_i mu_i|j x_i^j,  P0_j = sum_i mu_i|j (P_i^j + (x_i^j - x0_j)(x_i^j - x0_j)')
//                 where x_i^j, P_i^j is mode i's posterior seen by mode j. Mixed dimensions (choice):
//                 a state mode i lacks (CP's v and a, CV's a) is filled with mode j's own estimate
//                 of it and its variance, uncorrelated with the rest, so a mode keeps its own
//                 velocity / acceleration while another one dominates; a state mode j lacks is
//                 dropped. (The zero-fill alternative, a = 0 with variance p0_acc: on the generated
//                 tracks 212 instead of 214 of 216 within 10 % of the better single model, on
//                 E2 / E7 1.11 / 1.08 instead of 1.05 / 0.99 times it, tuning set-up below.)
//                 The CA mode is not mixed (mix_ca 0, the default; below): x0_ca = x_ca, P0_ca = P_ca.
//   mode-matched  x_j- = F_j x0_j,  P_j- = F_j P0_j F_j' + Q_j;  if z is measured:
//                 eps_j = z - x_j-(0),  S_j = P_j-(0,0) + R,  Joseph update of (x_j, P_j)
//   probabilities mu_j = c_j L_j / sum_i c_i L_i,  L_j = N(eps_j; 0, S_j) (in logs), floored at 1e-6
//                 so that every mode stays recoverable; without a measurement mu_j = c_j
//   combination   x = sum_j mu_j x_j,  P = sum_j mu_j (P_j + (x_j - x)(x_j - x)')  (the states a
//                 mode lacks count as 0 there: CP says v = a = 0)
// The innovation reported by innovation(c) is the moment-matched one of the mixture prior:
//   xbar = sum_j c_j x_j-(0),  eps = z - xbar,  S = sum_j c_j (S_j + (x_j-(0) - xbar)^2).
// Prediction query (const) to t = t_last + h (choice): each mode's posterior is extrapolated over
// h with its own model (the CA mode from its v and a weighted as kf-ca weighs them,
// channel_predictor.h: w_v = w(v, P_vv; shrink_v_sigmas), w_a = w(a, P_aa; shrink_sigmas), so the
// CA mode forecasts as kf-ca does) and the results are combined with the FORECAST WEIGHTS w_j, not
// with mu_j (forecast combination, choice):
//   e_j(k) = z_k - (F_j(dt) x^_j(k-1))(0),  s_j(k) = (F_j P_j(k-1) F_j' + Q_j)(0, 0) + R
//            (the forecast of this measurement made from mode j's own posterior of the previous
//            update, x^_j its forecast start as above; scored before mixing),
//   v_j(k) = clamp(c_j(k-1), 1e-12, 1) s_j(k),  c_j(k) = sum_i lambda^(k-i) r_j(i) / sum_i lambda^(k-i),
//            r_j = e_j^2 / s_j  (c_j: how far the realised squared errors are from the stated
//            variance, a prior ratio of 1 counted once at the start; calibration, below),
//   L_j(k) = lambda L_j(k-1) + l_j(k) - max_i l_i(k),  l_j = -(log v_j + e_j^2 / v_j) / 2,
//            lambda = exp(-dt / forecast_tau_s), then L_j <- max(L_j - max_i L_i, log forecast_floor),
//   w_j = exp(L_j) / sum_i exp(L_i);  without a measurement only the forgetting: L_j <- lambda L_j.
// Calibration (forecast_calibration, default 1; 0 scores with s_j, as before issue 11 item 4's
// second pass): the Gaussian score ranks modes by their squared errors only when each s_j is the
// variance its errors really have; where a mode states a larger variance than it has, the score
// pays it log s_j for nothing and favours the mode that states less. The CV and CA modes overstate
// theirs by different factors that depend on the frame period (q_cv T^3 / 3 against q_ca T^5 / 20:
// at 10 Hz the CA mode's one-frame Q is 0.15 px^2, the CV mode's 3.3 px^2): on `turns` 10 Hz
// 0.5 px #1 the CV mode's one-frame errors are 0.28 of its s (squared errors 4.1 px^2), the CA
// mode's 0.52 of its s (5.3 px^2); the score gave CA 0.86 of the forecast although its forecasts
// were the worse ones, at one frame (2.9 against 3.3 px) and at two (5.1 against 5.9 px).
// Lowering s_j to the realised c_j s_j makes the expected score -(log(E e_j^2) + 1) / 2, a ranking
// by squared error (there imm 5.17 px, kf-cv 5.10, before 5.72). A variance is only lowered,
// never raised (min(1, c_j)): the CP mode's squared errors on a moving target are 5 to over 100
// times its s, and that factor, carried into the next standstill, would keep it from taking over
// there (raising too, measured without the step fix below: 188 of the 216 tracks within 10 %
// instead of 215). c_j forgets with the weights' lambda (forecast_tau_s).
// The blend's step: the blend with hold (below) learns from d = sum_j w_j (p_j - z_hold), the
// combination of the modes' one-frame steps, which is exactly 0 when every mode forecasts z_hold
// (the first sample after the start); sum_j w_j p_j - z_hold was a rounding residual there (three
// thirds of z do not sum to z), whose least-squares weight y / d is clamped to 0 or 1 by its sign:
// imm then held the first frames of a fast start on a channel where the residual was negative
// (stops 10 Hz 0.5 px #504, 5 % drops: 11.1 px against kf-cv's 9.5; 9.4 with the fix). Which
// sign it has depends on the last bits of z (the same track read back from a CSV with 10
// significant digits gave 9.3 px).
// Each moving mode blended with hold on its own (blend_per_mode, default 1; 0 = the combination
// blended as above): with the blend on, the CV and CA modes each learn their own least-squares
// weight w_j on their own one-frame steps (the regression of channel_predictor.h, on p_j - z_hold),
// each mode's forecast is blended before the combination, sum_j w_fj (z_hold + w_j (p_j - z_hold)),
// CP's forecast unblended (it does not extrapolate), and the forecast weights score each mode's
// blended one-frame forecast (the hold and w_j of the update before; after a gap, the unblended
// one). Why: the blend is what makes kf-ca good at high frame rates, where its extrapolated
// acceleration is mostly noise and w shrinks it towards hold; blended on the combination, imm's
// CA mode had no such shrinking, its scores compared an unshrunk CA forecast with the CV one, and
// on fast weaves at 50-60 Hz imm was 1.2-1.5 times kf-ca. Scoring the unblended forecasts with the
// per-mode blend was worse there than either. Figures: docs/PERFORMANCE.md "imm blends each mode
// with hold".
// With the two weights (hold_blend_split, default 1; channel_predictor.h, "Two weights") each
// moving mode's blend splits its step at the mode's own start position p0_j (its posterior position;
// the CA mode's kept forecast start): z_hold + w_sj (p0_j - z_hold) + w_xj (p_j - p0_j) on a frame
// after a measured update, the one weight in a gap; the forecast weights score those forecasts.
// The combination's own regression (blend_per_mode 0) keeps one weight.
// The CA mode unmixed (mix_ca, default 0; 1 = mixed as the other modes, the standard IMM): the CA
// mode's prior is its own posterior of the last update; the CP and CV modes still mix from every
// mode, the CA mode's posterior included, and the mode probabilities follow the chain as above.
// Why: mixed, the CA mode's velocity was pulled every frame towards the CV mode's by the CV
// mode's share of the mixture it starts from, so the CA mode was not kf-ca, the single model it
// stands for: with the forecast weights forced onto it (a throw-away build) it forecast a weave
// of the second generator (60 Hz, 1 px, #1) with 7.90 px against kf-ca's 5.39, unmixed with 5.97
// (the rest is the raise of q, which the modes share, below). Mixing is how an IMM lets a mode
// start from the state of the mode the target comes from; the CA model contains the CV one
// (a = 0), so its own filter follows a switch to constant velocity by itself, at the pace its q
// allows. Not mixing the CV mode either (a bank of filters combined by the forecast weights) did
// worse on the second track generator. Figures: docs/PERFORMANCE.md "imm's CA mode unmixed".
// Coasting without the CP mode (coast_cp, default 0; 1 = as before): on a frame where a channel is
// not measured and coasting is on (coast_tau_s > 0), the CP mode's forecast weight is multiplied
// by coast_cp and the weights renormalised; the next measured frame recomputes them from the
// scores L_j, which the gap does not change but for the forgetting. Why: coasting already makes
// the moving modes' forecasts tend to hold through a gap (channel_predictor.h), so the CP share
// pulled imm's coasted forecast towards hold a second time. The CP weight was learnt on one-frame
// forecasts, where at 60 Hz the noise hides the motion (a CP share up to 0.98 in the first 0.5 s
// of smooth 60 Hz 3 px #3), and served a 14-frame extrapolation. Without coasting (the paper
// scenarios E7, E8 pin coast_tau_s = 0) the CP mode is imm's only pull towards hold in a gap and
// keeps its weight (measured on E7 with `extrapolate`: coast_cp 0 there would make imm 1.23 times
// kf-cv instead of 0.85). Figures: docs/PERFORMANCE.md "imm coasts without its CP mode".
// The forecast weights in a gap (gap_weight_power g, default 0.5; 1 = as before): on a frame where
// a channel is not measured, the forecast combines the modes with w_j proportional to
// exp(g L_j), the weights' evidence tempered (for g = 0.5 the normalised square roots of the
// weights; coast_cp above then applies); the next measured frame goes back to exp(L_j). A forecast
// made on a measured frame is the same bits for any g. Why: the evidence is of one-frame forecasts,
// and a gap's forecast extrapolates over the gap and the horizon; where the two rank the modes
// differently a whole-weight choice makes imm the worse single model through every gap. On the
// 47 tracks of make-track's four wide grids where imm missed 10 % of the better single model, its
// error in the gaps was nearer the worse model's than the better's on 45, while on the measured
// frames it was within 2 % of the better model's on 31 (docs/PERFORMANCE.md "imm's forecast
// weights in a gap", with the figures: 47 -> 29 misses there, none new; 30 -> 33 on the second
// generator; E7 without the lost-feature policy 0.86 -> 0.88 times kf-cv).
// This is dynamic model averaging with a forgetting factor (Raftery, Karny & Ettler, Technometrics
// 52(1), 2010) stated in seconds (so the same at any frame rate) on the modes' realised one-frame
// forecasts. Why not mu: mu_j rests on one-frame likelihoods of the MIXED priors, and the chain's
// prior pulls it to the stationary shares; on a long manoeuvre whose one-frame signature is below
// the noise (the closed loop's circle: 20 px/s^2 is 0.016 px per 40 ms frame under 0.5 px noise,
// and r = 1 px^2 pinned there) mu_cv stays near 0.6 and the forecast inherits the CV mode's lag.
// The forecast weights integrate the same kind of evidence over forecast_tau_s instead; the floor
// bounds how far behind a mode can fall (log 100 = 4.6 nats), so a switch with a clear signature
// is followed within a few frames (imm_test.cpp: 0.13 s into a 400 px/s^2 acceleration) while weak
// evidence accumulates to a clear choice. The floor also keeps a 1 % share of each other mode in
// every forecast. The filter itself (mixing, mu) is the IMM above; a query at t <= t_last (zero
// horizon) combines the posteriors with the forecast weights too (in a closed loop with the
// feed-forward's weights: "The feed-forward's velocity", below). forecast_tau_s = 0 gives every
// query combined with mu, as before issue 11 item 4 was closed.
// Measured choices (docs/PERFORMANCE.md "IMM"): scoring the 2- or 3-frame forecasts instead of the
// 1-frame ones, or the sum of the 1- and 2-frame scores, lost 5-11 of the 216 tracks (measured
// again with the calibration and before the step fix, 2 frames: 213 instead of 215 of 216; the
// squared errors alone with a common variance, no log term: 200-213); floor 1e-6
// (recovery needs 13.8 nats) left E2 at 1.20 times kf-ca; forecast_tau_s 3 s left the closed
// loop at 1.6 times kf-ca, 10 / 30 / 60 s give 0.91 / 0.81 / 0.80 with the tracks unchanged
// (210-211 of 216). Weighting with mu propagated by the chain over h (an earlier choice) mixes in
// the full-horizon extrapolation of a mode the target would only switch to part-way: E2 1.20.
// The raise of q on each mode (q_raise_cv_exponent, default 0.5; 1 = both modes alike, as before):
// the raise (process_noise_adapt.h, one scale s per channel) multiplies the CA mode's density by s
// and the CV mode's by s^q_raise_cv_exponent. s observes the CA mode's own innovation eps_CA, S_CA
// (q_raise_from_ca, default 1; 0 = the combination's moment-matched innovation, as before), in the
// open loop's raise and the closed loop's whitening alike. Why: the CA mode starts from its own
// posterior (mix_ca 0, above), so observed on its own innovation it is raised, and whitened, as
// kf-ca raises and whitens itself: the single model it stands for. The combined innovation mixes in
// the CV mode's lag (or, in a closed loop where mu favours the CV mode, is nearly the CV mode's
// own), and the CA mode's density followed that instead. Measured (docs/PERFORMANCE.md "imm's raise
// on its CA mode's own innovation"): imm over 1.1 times the better of kf-cv and kf-ca on the second
// generator 6 -> 1 and 3 -> 0 of 576 tracks (seeds 1-4, 5-8), on make-track's ten grids 50 -> 48,
// 5 frames ahead 81 -> 74 and 11 -> 6; its error 2-4 % lower on the closed-loop grids (none worse
// than +1.6 %). Why the CV mode is raised less: a manoeuvre the
// defaults were not sized for is the CA mode's to carry; raised as much, the CV mode follows it too,
// with a lag that one-frame forecasts hide under the noise, keeps the forecast weight and gives
// imm its lag (a weave of 3000 px/s^2 at 30 Hz, 2 px: CV forecast weight 0.92-0.98 for the whole
// track, imm 1.5 times kf-ca's error). Measured on both track generators (docs/PERFORMANCE.md "imm
// raises its CV mode less"); 0 (the CV mode never raised) won as much on the second generator and
// cost more on make-track's drop grids. The exponent damps raises only: when the scale falls below 1
// (the closed loop's whitening, below; `q: auto`) the CV mode's density falls by s as the CA mode's.
// Why: falling by s^0.5, at the scales of 0.001-0.01 the whitening reaches on the default loop, kept
// the CV mode's density 10-30 times higher, relative to its default, than the CA mode's, and on the
// default loop's fast target imm stayed
// 1.1-1.3 times kf-ca (4 of 12 held-out variants over 1.1; none with the CV mode lowered alike;
// docs/PERFORMANCE.md "imm lowers its CV mode as much as its CA mode"). The open loop's raise never
// falls below 1: the same bits there.
// In a closed loop (`closed_loop: 1`, predictor.h) imm runs without its CP mode unless `cp` is
// given. The loop's feed-forward takes imm's velocity (feedforwardVelocity()): CP's share of the
// forecast weights scales it down (CP says v = 0), and mixing CP's position, which lags a moving
// target, into the CV mode's prior every frame biases the CV mode's velocity up to make the lag
// good (on e5-line's 5 px/s leader the fed-forward velocity averaged 7.4 px/s with a standard
// deviation of 16). Leaving CP out of the mixing alone gave e5-line 2.3 px instead of 2.7; without
// the mode imm is the IMM of kf-cv's and kf-ca's models, 0.8 px (10 seeds; docs/PERFORMANCE.md
// "Innovations made white"). In the open loop the CP mode stays: it is imm's own judgement of hold.
// The feed-forward's velocity (feedforwardVelocity(); channel_predictor.h, "The feed-forward's
// velocity"): sum_j u_j (F_j x_ff_j)(1) over the moving modes, times w_ff, with x_ff_j the mode's
// feed-forward start (the CA mode's velocity not weighted by its significance) and w_ff learnt, as a
// channel filter's, on the combination's one-frame step sum_j u_j d_j, d_j = (F_j x_ff_j)(0) - x_ff_j(0).
// The weights u_j are the feed-forward's own: each moving mode's step D_j and the measured step Y_w,
// both low-passed with ff_weight_tau_s (default 2 s; w_ff's pair uses kFeedforwardTauS, 1 s), are
// compared, the forgetting sums S_j = sum lambda^(k-i) (Y_w - D_j)^2 are kept (lambda the blend's), and
//   u_j = (min_i S_i / S_j)^16 / normalisation  (equal shares before the first sample; CP's 0),
// so a mode's share halves for every 4.4 % of error more than the best one's. Why 2 s and not w_ff's
// 1 s: the loop integrates the feed-forward over its own time constant (2 s at lambda 0.5), so a lag
// that lasts is what it cannot undo, while noise it averages; over 1 s at 10 Hz under 5 px of noise
// the CA mode's noisier steps still outweighed the CV mode's lag: on e8-ibvs u left the image's u
// channels to the CV mode through the board's 10 s of deceleration and gave them to the CA mode only
// once its speed had reversed (CA share 0.02-0.33 before 10 s, 0.17-0.68 at 10 s; imm 1.13 times
// kf-ca; with the CA mode's velocity alone 0.91); over 2 s the CA mode gets 0.1-0.5 of them during
// the deceleration and 0.70-0.99 at 10 s (the v channels stay with the CV mode either way).
// 2 s: e8-ibvs 0.96 times kf-ca, e8-vtc 1.18 -> 1.13 px, the other
// closed-loop cells within -1 % .. +2 % (e5-circle); 1.5-4 s alike, 0.5 s far worse
// (docs/PERFORMANCE.md "imm's feed-forward weights over two seconds"). At a zero horizon
// the posteriors' velocities are mixed by u, without w_ff (as the channel filters' zero horizon),
// and in a closed loop so is the whole state predict() hands out there (position, covariance): the
// loop's query without vision delay acts on that position (`servo.forecast: both`), and the forecast
// weights, which rank one-frame forecasts, gave e8-ibvs's CV mode 0.99 of it while kf-ca's position
// served the loop better (imm 1.22 times kf-ca on e8-ibvs, 1.13 with u; e8-vtc 1.24 -> 1.18 px;
// the other 34 closed-loop cells of that measurement are the same bits; docs/PERFORMANCE.md "imm's
// zero horizon in a closed loop").
// u and w_ff are learnt only when imm is told it serves a closed loop (`closed_loop: 1`, predictor.h)
// with the blend on: the feed-forward's one caller is the servo loop, and on `predict`'s 2-million-row
// track the learning cost 0.13 s of CPU (imm alone 2.04 -> 2.17 s, docs/PERFORMANCE.md "A lagging
// acceleration model in the closed loop") for weights nobody read. Otherwise (and without the blend,
// hold_blend_tau_s 0: the papers' scenarios) the feed-forward's velocity is the forecast-weighted one
// it was before them (predict()'s at a zero horizon).
// Why: the forecast weights score one-frame positions, where the two models differ by less than
// the noise; on e5-line's 5 px/s leader they gave the CA mode 0.96 of the velocity, whose noise the
// law then integrated, while u gives the CV mode 0.65-0.73. Measured (10 seeds, 24 closed-loop
// cells, every predictor at its defaults; docs/PERFORMANCE.md "A lagging acceleration model in the
// closed loop"): imm / min(kf-cv, kf-ca) over 1.1 on 2 cells (e5-line 1.14, e8-ibvs 1.16) instead of
// 10 with the forecast weights and no w_ff, and 3 with w_ff alone (since the CV mode's exponent on
// raises only and the zero horizon mixed by u, above: on 1 of 36 cells, e8-ibvs 1.13; since u's
// 2 s low-pass, on none). A power of 4 left 4 over (e9-broyden's
// gains 6 and 7 too), 1000 (the better mode alone) 2 (e8-ibvs 1.18). Each mode whitened on its own
// innovations instead of the shared scale made the modes kf-cv and kf-ca to 1 %, but then the
// weights u chose the worse of the two on delay-study (1.18-1.34); the CV mode alone on its own
// whitening lost 6 of 12 held-out variants of the default loop (up to 2.84 times). The one shared
// scale observing the CA mode's innovation (q_raise_from_ca, above) is what is kept.
// Parameters (px and s): q_cp (px^2/s, default 2), q_cv (px^2/s^3, default kDefaultQCv), q_ca
// (px^2/s^5, default kDefaultQCa; when neither q_cv nor q_ca is given and the blend with hold is
// on, both are raised, per channel, while the CA mode's innovation (the combined one with
// q_raise_from_ca 0, above) is more than q_raise_ratio (default 2; 0 = no raise) times its
// predicted variance: process_noise_adapt.h; the CV mode by the raise to the power
// q_raise_cv_exponent, above; in a closed loop, `closed_loop: 1`, the same scale is moved until
// those innovations are white instead, down as well as up:
// process_noise_adapt.h, predictor.h closedLoopParam; q_white_rho, the whiteness aimed at, default
// kDefaultQWhiteRhoAcceleration: process_noise_adapt.h, "The whitening's target"),
// alpha (1/s, default 0: CA; > 0: Singer), r (px^2; default `auto`,
// predictors/noise_estimate.h; a number fixes it), tau_cp_s (5), tau_cv_s (30), tau_ca_s (3)
// (stationary shares 13 / 79 / 8 %), cp (1, and 0 with `closed_loop: 1`, below; 0 leaves the CP
// mode out), p0_vel ((px/s)^2, 1e4),
// p0_acc ((px/s^2)^2, 1e4), coast_tau_s (s, default kDefaultCoastTauS; 0 = off): on a frame with
// no measurement, each mode's mixed velocity and acceleration decay before its time update, the
// law of every other predictor (channel_predictor.h, docs/MODELS.md §15), so imm coasts like its
// single models; forecast_tau_s (s, default 30; 0 = forecast with mu), forecast_calibration (1;
// 0 = the forecast weights score with the model's s_j, above), forecast_floor
// (relative weight, default 0.01, in [1e-12, 0.5]); coast_cp (in [0, 1], default 0; above);
// mix_ca (0 or 1, default 0; above); q_raise_from_ca (0 or 1, default 1; above);
// gap_weight_power (in [0, 1], default 0.5; above);
// ff_weight_tau_s (s, in [0.001, 1e6], default 2: the low-pass of the feed-forward's weights u in a
// closed loop; above);
// shrink_sigmas and shrink_v_sigmas (the CA
// mode's forecast weighting, kf-ca's keys and defaults: 2 and 2; 0 = unweighted). hold_blend_tau_s (s,
// default kDefaultHoldBlendTauS; 0 = off): the
// forecast blended with hold by the least-squares weight of the one-frame forecasts, as every
// per-channel filter's (channel_predictor.h): each moving mode's by its own weight, or with
// blend_per_mode 0 the combination's (above); hold_blend_frames (1..8, default 2, as theirs): each
// of those weights is the smallest of its regressions on the forecasts of 1..H frames (Channel::
// starts keeps the forecast starts of the last updates); hold_blend_split (0 | 1, default 1, as
// theirs): each moving mode's weight split in two (above); hold_blend_prior (default 4, as theirs;
// 0 = off): every one of those regressions hands out its weights times 1 - exp(-(c / p)^2) after
// c samples (channel_predictor.h, "The start of a track"); extrapolation_cap (default 4, as theirs;
// 0 = off): with the split, each moving mode's forecast extrapolates from its start position at most
// rho times the RMS rate of that mode's one-frame extrapolations (Channel::mode_rates;
// channel_predictor.h, "Extrapolations the track has not shown"); with it, coast_stop_fraction (default 0.5; 0 = off):
// a gap that begins while the mu-combined velocity falls coasts with a shorter time constant
// (channel_predictor.h, "A stop before the gap"), and coast_lag_sigmas (default 2; 0 = off): one
// that begins while the moment-matched innovations of the last 5 measured frames oppose that
// velocity by more than 2 sigma too, cut no further than the share of its step the combined velocity
// still made (coast_lag_share, default 1; channel_predictor.h, "Measurements falling behind"), and
// coast_crossing (default 1; 0 = off):
// one that begins just after the combined velocity fell through zero carries the CA mode's
// acceleration times the share of the channel's earlier crossings that turned (channel_predictor.h,
// "A turn or a stop through zero"; the crossings are watched on the combined velocity). The initial
// mode probabilities and forecast weights are equal. q_cp and the tau were chosen
// on the generated tracks (servo/maneuver_tracks.h) and the paper scenarios E1-E4, E7 together
// (docs/PERFORMANCE.md "IMM against its single models"); they are not sharp optima (one at a
// time, tau_cv 10 / 100 s, tau_ca 1 / 10 s, tau_cp 2 / 10 s, q_cp 1 / 5 px^2/s: 210-214 of 216
// tracks within 10 %, E1-E7 at most 1.13 times the better single model). Tuning set-up of the
// figures in this comment: the 216 tracks with defaults; E1-E4 and E7, 10 runs, imm with
// q_cv = 100, q_ca = 1000, r = 1 on all of them (E7's file now pins q_cv = 200, r = 5 as its kf-cv)
// against kf-ca with q = 1000, r = 1.
// Forecast weights: forecastWeight(c, mode). Mode probabilities: modeProbability(c, mode). Both in
// diagnostics(), "mu_cp_<c>", "mu_cv_<c>", "mu_ca_<c>" and then "fw_cp_<c>", "fw_cv_<c>",
// "fw_ca_<c>" (a mode the instance lacks has no column): the log.csv of `predvs servo`, open or
// closed loop, writes them as trailing columns (empty on the other predictors' rows; in closed loop
// channel c is the task's feature c, the values those after the last delivered frame).
#pragma once

#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/kalman_math.h"
#include "predvs/predictors/noise_estimate.h"
#include "predvs/predictors/predictor.h"
#include "predvs/predictors/recent_values.h"

#include <array>
#include <optional>
#include <vector>

namespace predvs {

/// The modes of imm: constant position (random walk), constant velocity, constant / Singer acceleration.
enum class ImmMode { Cp, Cv, Ca };
/// "cp", "cv", "ca".
const char* immModeName(ImmMode m);

class ImmPredictor : public Predictor {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<ImmPredictor>(*this); }
  static constexpr int kMaxModes = 3;
  ImmPredictor(int channels, const Params& params);
  std::string name() const override { return "imm"; }
  void reset() override;
  void update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) override;
  using Predictor::update;
  ChannelEstimate predict(int channel, double t_s) const override;
  /// predict(channel, t_s).position() without the covariances: sum_j mu_j (F_j x_j)(0), the same
  /// arithmetic in the same order (bit for bit).
  double predictPosition(int channel, double t_s) const override;
  /// w_ff sum_j u_j (F_j x_j)(1) of the moving modes' feed-forward starts (feedforwardStartMean()), u
  /// the feed-forward's weights (file comment, "The feed-forward's velocity"), without the modes'
  /// blends with hold (Predictor::feedforwardVelocity()); at a zero horizon sum_j u_j v_j of the
  /// posteriors.
  double feedforwardVelocity(int channel, double t_s) const override;
  Innovation innovation(int channel) const override { return chan_.at(static_cast<size_t>(channel)).innovation; }
  NamedValues diagnostics() const override;
  /// q_cv, q_ca and r: the number given, or, when `r` is `auto`, the estimator's prior (1 px^2).
  std::vector<NoiseParameter> noiseParameters() const override {
    return {accelerationDensityParameter("q_cv", q_cv_), jerkDensityParameter("q_ca", q_ca_),
            measurementVarianceParameter(r_)};
  }
  /// q_cv from kf-cv's fitted q and, on the CA mode (alpha = 0), q_ca from kf-ca's: its CV and CA
  /// modes are those filters' models (imm.cpp, at the end).
  std::vector<FitSeed> fitSeeds() const override;
  /// {cp: 1} and {cp: 0}: with and without the constant-position mode (imm.cpp, at the end). The
  /// default prediction is unchanged (a fit tries both and keeps the better on its rows).
  std::vector<Params> structuralVariants() const override;

  /// Number of modes (2 without the CP mode, 3 with it).
  int modeCount() const { return static_cast<int>(modes_.size()); }
  /// Probability of `mode` on channel c after the last update (0 for a mode this instance lacks).
  double modeProbability(int c, ImmMode mode) const;
  /// Weight of `mode` in the forecast of channel c (forecast combination, above; the mode
  /// probability when forecast_tau_s = 0; 0 for a mode this instance lacks).
  double forecastWeight(int c, ImmMode mode) const;
  /// R used by channel c now (px^2).
  double measurementNoise(int c) const;
  /// Mode transition probabilities p_ij over dt (rows: from, columns: to; in modes' order).
  using ModeMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxModes, kMaxModes>;
  ModeMatrix chain(double dt) const;

 private:
  struct Mode {
    ImmMode kind;
    int dim;  ///< states of [p, v, a] the model has: 1, 2 or 3
    double tau_s;  ///< mean sojourn time
  };
  struct Channel {
    std::array<Gaussian<3>, kMaxModes> g;
    std::array<double, kMaxModes> mu{};
    std::array<double, kMaxModes> logw{};  ///< forecast log weights (forgetting evidence), max 0
    std::array<double, kMaxModes> fw{};    ///< forecast weights: exp(logw) normalised
    /// Calibration of each mode's forecast variance: the forgetting mean of e_j^2 / s_j (a prior
    /// ratio of 1 counted once), and the forgetting count of the ratios it holds.
    std::array<double, kMaxModes> fc_cal{};
    double fc_cal_n = 1.0;
    bool initialized = false;
    Innovation innovation;
    StartupNoiseEstimator r_est;
    HoldBlend blend;  ///< the blend with hold (channel_predictor.h)
    /// The feed-forward (file comment, "The feed-forward's velocity"): w_ff's regression on the
    /// combination's one-frame step, each moving mode's one-frame step low-passed with
    /// ff_weight_tau_s, D_j, and the forgetting sum of (Y_w - D_j)^2 (Y_w = ff_y, the measured step
    /// low-passed alike), and the weights the feed-forward combines the modes with (equal shares of
    /// the moving modes until the first sample; CP's is 0).
    FeedforwardWeight feedforward;
    std::array<double, kMaxModes> ff_step{}, ff_sq{}, ff_w{};
    /// The measured step low-passed with ff_weight_tau_s, against which the weights judge ff_step.
    double ff_y = 0.0;
    bool last_measured = false;
    /// The raise of q (process_noise_adapt.h); its scale stays 1 unless q_raise_ is set.
    ProcessNoiseMatcher q_raise;
    /// The CV mode's share of the raise: q_raise.scale()^q_raise_cv_exponent (the CA mode's is the scale).
    double q_raise_cv = 1.0;
    /// Each mode's own blend weight with hold (blend_per_mode; the hold and the gap's coasting are
    /// blend's).
    std::array<BlendWeight, kMaxModes> mode_blend{};
    /// Each blended mode's one-frame extrapolation rates, for its cap (extrapolation_cap).
    std::array<ExtrapolationRates, kMaxModes> mode_rates{};
    /// The blend on more than one horizon (hold_blend_frames H, channel_predictor.h): the forecast
    /// starts of the last measured updates (ring, newest at start_head; start_run of them in a row)
    /// and the regressions on the forecasts of h = 2..H frames, combined (longer[h - 2]) and per mode
    /// (mode_longer[j][h - 2]). The weights handed out are the minima over the horizons.
    struct BlendStart {
      std::array<Vec<3>, kMaxModes> x{};      ///< each mode's forecast start (forecastStartMean's for CA)
      std::array<double, kMaxModes> fw{};     ///< the forecast weights then
      double z_hold = 0.0, t_s = 0.0;         ///< the hold and the time of that update
    };
    std::array<BlendStart, kMaxBlendFrames> starts{};
    int start_head = 0, start_run = 0;
    LongerBlendWeights longer{};
    std::array<LongerBlendWeights, kMaxModes> mode_longer{};
  };
  /// (F_j(dt) x)(0): mode j's position dt ahead of the state x (row 0 of transition(j, dt) written out).
  double forecastPosition(int j, const Vec<3>& x, double dt) const;
  /// Keeps the forecast starts of channel ch after its measured update at t_s (Channel::starts).
  void rememberBlendStart(Channel& ch, double t_s) const;
  /// The regressions of h = 2..blend_frames_ frames on the measured frame z at t_s (lambda the
  /// blend's forgetting), and the weights handed out: the minima over the horizons.
  void learnLongerBlend(Channel& ch, double t_s, double z, double lambda) const;
  Mat<3> transition(int j, double dt) const;
  /// Mode j's Q over dt, the CV or CA density multiplied by `scale` (mode j's raise of q, modeRaise()).
  Mat<3> processNoise(int j, double dt, double scale = 1.0) const;
  /// The factor of the raise of q on mode j of channel ch: 1 for CP, q_raise_cv for CV, the scale for CA.
  double modeRaise(const Channel& ch, int j) const;
  /// Q (each mode's over this dt) with the channel's raise applied (modeRaise()): Q itself when the
  /// scale is 1, else the scaled copies written into scratch.
  const std::array<Mat<3>, kMaxModes>& raisedProcessNoise(const Channel& ch, const std::array<Mat<3>, kMaxModes>& Q,
                                                          std::array<Mat<3>, kMaxModes>& scratch) const;
  Gaussian<3> combine(const std::array<Gaussian<3>, kMaxModes>& g, const std::array<double, kMaxModes>& w) const;
  /// The mixed prior of mode j from the posteriors g with weights w (mixing, above), on the states
  /// mode j has (the others 0): combine() of the posteriors as mode j sees them, the same bits there.
  void mixInto(const std::array<Gaussian<3>, kMaxModes>& g, const std::array<double, kMaxModes>& w, int j,
               Gaussian<3>& out) const;

  double q_cp_, q_cv_, q_ca_, alpha_, r_, p0_vel_, p0_acc_;
  /// The raise of q, set when it is on (q_cv and q_ca not given, the blend on, q_raise_ratio > 0).
  std::optional<ProcessNoiseMatcher> q_raise_;
  double coast_tau_s_;  ///< s; 0 = no coasting
  double fc_tau_s_;     ///< s; forgetting time of the forecast weights' evidence; 0 = forecast with mu
  double fc_floor_;     ///< log of forecast_floor: the lowest log forecast weight relative to the best
  bool fc_calibrate_;   ///< forecast_calibration: score with v_j = min(1, c_j) s_j instead of s_j
  double shrink_a_sigmas_, shrink_v_sigmas_;  ///< the CA mode's forecast weighting (kf-ca's); 0 = off
  double blend_tau_s_;  ///< s; the forecast's blend with hold (hold_blend_tau_s, channel_predictor.h); 0 = off
  /// hold_blend_frames (channel_predictor.h): the blend's weight is the minimum over 1..H frames. Not
  /// a forecast variant (Predictor::forecastVariants()): the mode probabilities score each mode's
  /// blended forecast, so H changes imm's filter too (PredictorProperty.ForecastVariantsChangeTheForecastOnly).
  int blend_frames_;
  double blend_sigmas_;  ///< hold_blend_sigmas (channel_predictor.h)
  double blend_prior_;   ///< hold_blend_prior (channel_predictor.h, "The start of a track"), every weight
  bool blend_split_;     ///< hold_blend_split (channel_predictor.h, "Two weights"), per mode
  double extrapolation_cap_;  ///< extrapolation_cap (channel_predictor.h), per blended mode with the split
  double coast_stop_fraction_;  ///< coast_stop_fraction (channel_predictor.h), with the blend only
  double coast_fast_ratio_;  ///< coast_fast_ratio (channel_predictor.h), with the blend only
  double coast_lag_sigmas_;  ///< coast_lag_sigmas (channel_predictor.h), with the blend only
  bool coast_lag_share_;     ///< coast_lag_share (channel_predictor.h), with the blend only
  double coast_shape_;       ///< coast_shape (channel_predictor.h), with the blend only
  bool coast_crossing_;      ///< coast_crossing (channel_predictor.h): the CA mode's acceleration at a gap after a crossing
  double coast_cp_;  ///< coast_cp: factor on the CP mode's forecast weight on an unmeasured frame while coasting
  double gap_weight_power_;  ///< gap_weight_power: the power of the forecast weights on a frame without a measurement
  double q_raise_cv_exponent_;  ///< q_raise_cv_exponent: the CV mode's density rises as the raise to this power
  /// q_raise_from_ca: the raise (the whitening in a closed loop) observes the CA mode's own innovation,
  /// as kf-ca's observes its own (false: the combination's moment-matched innovation).
  bool q_raise_from_ca_;
  double ff_weight_tau_s_;  ///< ff_weight_tau_s: the low-pass of the feed-forward's weights' steps (s)
  /// blend_per_mode: with the blend on, each mode's forecast is blended with hold by its own weight
  /// before the combination, and the forecast weights score the blended one-frame forecasts.
  bool blend_per_mode_;
  /// mix_ca: the CA mode's prior is mixed from every mode's posterior, as the other modes' are
  /// (false: it starts from its own posterior; imm.h, "The CA mode unmixed").
  bool mix_ca_;
  /// True when the feed-forward's weights and w_ff are learnt: told `closed_loop: 1`, with the blend
  /// on (file comment, "The feed-forward's velocity").
  bool learn_feedforward_ = false;
  /// True when the blend with hold is applied per mode (blend_per_mode_ and the blend on).
  bool blendsPerMode() const { return blend_per_mode_ && blend_tau_s_ > 0.0; }
  /// True when mode j's forecast is blended with hold by its own weight: blendsPerMode() and a
  /// mode that extrapolates (CV, CA; CP's forecast stays where its posterior is, nothing to shrink).
  bool blendsMode(int j) const { return blendsPerMode() && modes_[static_cast<size_t>(j)].dim > 1; }
  /// True when the modes' forecasts of channel ch now are blended with the two weights
  /// (channel_predictor.h, "Two weights"): the split is on and the last update was measured.
  bool splitsBlend(const Channel& ch) const { return blend_split_ && ch.last_measured; }
  /// The mu-combined velocity of channel ch's posterior (px/s) and its variance (spread included).
  double combinedVelocity(const Channel& ch) const;
  double combinedVelocityVariance(const Channel& ch) const;
  /// Mode j's posterior on channel ch as its forecast starts from: the CA mode's v and a weighted
  /// as kf-ca weighs them (channel_predictor.h), the other modes' unchanged.
  Gaussian<3> forecastStart(const Channel& ch, int j) const;
  /// The mean of forecastStart(ch, j) alone.
  Vec<3> forecastStartMean(const Channel& ch, int j) const;
  /// The start of mode j's feed-forward velocity: forecastStartMean() without the CA mode's weight
  /// on its velocity (channel_predictor.h, "The feed-forward's velocity").
  Vec<3> feedforwardStartMean(const Channel& ch, int j) const;
  /// The weights the forecast combines the modes with on channel ch: mu, or the forecast weights.
  const std::array<double, kMaxModes>& forecastWeights(const Channel& ch) const {
    return fc_tau_s_ > 0.0 ? ch.fw : ch.mu;
  }
  /// The weights the feed-forward's velocity combines the modes with on channel ch: its own (file
  /// comment, "The feed-forward's velocity") when it learns them, else the forecast's, as before them.
  const std::array<double, kMaxModes>& feedforwardWeights(const Channel& ch) const {
    return learn_feedforward_ ? ch.ff_w : forecastWeights(ch);
  }
  /// The feed-forward's sample of channel ch on a measured frame z after a measured one, F the
  /// modes' transitions over the frame, lambda the blend's forgetting, a w_ff's low-pass and a_w the
  /// weights' (ff_weight_tau_s): w_ff's regression on the combination's step, then each moving
  /// mode's error and the modes' weights (file comment, "The feed-forward's velocity").
  void learnFeedforward(Channel& ch, double z, const std::array<Mat<3>, kMaxModes>& F, double lambda, double a,
                        double a_w) const;
  /// ch.fw from ch.logw: exp(power logw_j), normalised (power < 1 on a frame without a measurement).
  void normaliseForecastWeights(Channel& ch, double power = 1.0) const;
  bool r_auto_;
  std::vector<Mode> modes_;
  ModeMatrix rates_;
  // Everything of a frame period dt that is the same for every channel: the chain's p_ij(dt), each
  // mode's F and Q, the forecast weights' forgetting exp(-dt / forecast_tau_s) and the blend's
  // exp(-dt / hold_blend_tau_s). Kept for the last kChainCacheSize distinct dt asked, replaced in
  // turn: the frame period of a recorded track takes a handful of values (times written with 10
  // significant digits give differences that vary in their last bits, 54 distinct ones on the
  // 2-million-row track of docs/PERFORMANCE.md, a few at a time: a new dt on 92 % of its frames),
  // so one entry is too few (recent_values.h). Each entry is what computeChain(dt), transition(),
  // processNoise() and std::exp return for dt, so the results are the same bits. Mutable cache of a
  // const function; an instance is used by one thread at a time.
  static constexpr int kChainCacheSize = 8;
  struct PeriodModels {
    ModeMatrix chain;
    std::array<Mat<3>, kMaxModes> F, Q;
    double keep = 0.0, blend_keep = 0.0, feedforward_keep = 0.0, ff_weight_keep = 0.0;
  };
  ModeMatrix computeChain(double dt) const;
  const PeriodModels& periodModels(double dt) const;
  mutable RecentValues<PeriodModels, kChainCacheSize> period_models_;
  /// exp(-dt / hold_blend_tau_s) for the time dt since a channel's last measurement (the forgetting
  /// of the blend's recent speeds), kept for the last few distinct dt as the per-channel filters'
  /// blendForgetting (channel_predictor.h): the same bits as std::exp, no exp per measured frame.
  double blendForgetting(double dt) {
    return blend_gap_keep_.get({dt}, [&] { return std::exp(-dt / blend_tau_s_); });
  }
  RecentValues<double> blend_gap_keep_;
  /// exp(log forecast_floor): the forecast weight of a floored mode before normalising.
  double fc_floor_exp_ = 0.0;
  std::vector<Channel> chan_;
};

}  // namespace predvs
