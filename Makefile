# predvs — top-level convenience targets. Each target does the set-up it needs.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
PREDVS := $(BUILD_DIR)/app/predvs

.PHONY: deps configure build run test bench golden reproduce deb deb-check clean

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DPREDVS_BUILD_TESTS=ON -DPREDVS_BUILD_BENCHMARKS=ON >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The main job: the default scenario (IBVS on a moving target, 2-frame vision delay),
# comparing no prediction (hold) with kf-cv and cs-akf-adaptive.
run: build
	$(PREDVS) servo

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/bench/predvs_bench --benchmark_counters_tabular=true

# Regenerates the golden trace of the default scenario (see tests/servo) and the mire-2 golden
# track and prediction errors of `predvs track` (see tests/app/track_command_test.cpp).
MIRE2 := /usr/share/visp-images-data/ViSP-images/mire-2/image.%04d.pgm
# (the mire-2 errors pin the predictors themselves: without track's glitch gate, as the test runs them)
golden: build
	$(PREDVS) servo --out $(BUILD_DIR)/golden-run --no-plots
	cp $(BUILD_DIR)/golden-run/log.csv data/golden/ibvs-moving-target.csv
	$(PREDVS) track --images $(MIRE2) --source dots --predictor all --glitch-sigmas 0 --delay-frames 1 --fps 30 --no-plots --strip-frames 0 --out $(BUILD_DIR)/golden-mire2 && cp $(BUILD_DIR)/golden-mire2/tracks_wide.csv data/golden/mire-2-dots.csv && cp $(BUILD_DIR)/golden-mire2/leaderboard.csv data/golden/mire-2-prediction-h1.csv

# Every figure of docs/REPRODUCTION.md: one leaderboard per paper (and the closed loop) under
# out/reproduction/, the studies the page quotes beside them (a_max and floor sweeps, the fuzzy
# layers of fakf, stkf's tuning in the closed loop, the monitor's band) and the E7
# re-initialisation count printed by its unit test (about 80 s on 2 cores).
# fakf with each fuzzy layer switched off (R held at 1 px^2 by its clamp; P inflation never due).
FUZZY_LAYERS := cs-akf-adaptive,fakf,fakf-fixed-r=fakf:r_min=0.9999:r_max=1.0001,fakf-no-inflation=fakf:inflation_period=1000,fakf-neither=fakf:r_min=0.9999:r_max=1.0001:inflation_period=1000,csa-r06=cs-akf-adaptive:r=0.6
# stkf in the closed loop: the squared R, the self-tuning, R_0 and Q_0 changed one at a time.
STKF_TUNING := hold,kf-cv,stkf,stkf-unsquared=stkf:squared=0,stkf-plain=stkf:window=0,stkf-r025=stkf:r=0.25,stkf-qpos0=stkf:q_pos=0,stkf-qvel200=stkf:q_vel=200
PAPER000 := hold,kf-cv,kf-ca,cs-akf,cs-akf-adaptive,fakf-classic,fakf,imm
CLOSED := hold,kf-cv,kf-ca,cs-akf,cs-akf-adaptive,fakf,stkf,st-akf,imm:q_cv=100:q_ca=1000:r=1:shrink_sigmas=0:hold_blend_tau_s=0:cp=1
# Predictors a line adds to scenarios that do not list them run with the defaults before issue 11.
PRE11 := data/params/pre-issue-11.yaml
# (imm in CLOSED: its CV and CA modes as the scenario's kf-cv and the kf-ca of PRE11, like for like;
# the paper scenario files pin it the same way; cp=1 keeps its CP mode, which a closed loop leaves
# out by default since 2026-12-05: docs/PERFORMANCE.md "Innovations made white".)
reproduce: build
	$(PREDVS) compare --scenarios e1-line,e2-accel-jump,e3-zigzag,e4-circle,e4-circle-large --predictors $(PAPER000) --params $(PRE11) --out out/reproduction/paper000
	$(PREDVS) compare --scenarios e5-line,e5-circle,e5-line-ibvs,e5-circle-ibvs --out out/reproduction/paper000-e5
	$(PREDVS) compare --scenarios e5-line,e5-line-ibvs --sweep target.trajectory.vy=0.0002,0.0005,0.001,0.002,0.004 --out out/reproduction/paper000-e5-speed
	$(PREDVS) compare --scenarios e5-line,e5-circle --sweep task.q_near=0.5,1,2,4,8,12 --out out/reproduction/paper000-e5-gain
	$(PREDVS) compare --scenarios e5-line-ibvs,e5-circle-ibvs --sweep task.lambda=0.75,1.25,2.25,4.25,8.25,12.25 --out out/reproduction/paper000-e5-gain-ibvs
	$(PREDVS) compare --scenarios e6-noise-study --out out/reproduction/paper001-e6
	$(PREDVS) compare --scenarios e7-occlusion --predictors hold,kf-cv,kf-ca,cs-akf-adaptive,fakf-classic,fakf,stkf,st-akf,imm --sweep lost.action=extrapolate,hold --params data/params/e7-like-for-like.yaml --out out/reproduction/paper001-e7
	$(PREDVS) compare --scenarios e8-vtc,e8-vtc-occlusion,e8-ibvs --out out/reproduction/paper001-e8
	$(PREDVS) compare --scenarios e8-vtc --sweep timing.delay_frames=0,1,2 --out out/reproduction/paper001-e8-delay
	$(PREDVS) compare --scenarios e9-broyden,e9-broyden-uncompensated,e9-ibvs --out out/reproduction/paper002-e9
	$(PREDVS) compare --scenarios e10-rotation-150,e10-rotation-30 --out out/reproduction/paper003-e10
	$(PREDVS) compare --scenarios e11-depth-error --out out/reproduction/paper003-e11
	$(PREDVS) compare --scenarios e12-discontinuity,e12-discontinuity-2ms,e12-smooth --out out/reproduction/paper004
	$(PREDVS) compare --scenarios ibvs-moving-target --predictors $(CLOSED) --params $(PRE11) --out out/reproduction/closed-loop
	$(PREDVS) compare --scenarios delay-study --out out/reproduction/delay-study
	$(PREDVS) compare --scenarios e2-accel-jump --params $(PRE11) --predictors cs-akf --sweep predictors.cs-akf.params.a_max=5,20,50,100,200,500 --out out/reproduction/paper000-e2-a-max
	$(PREDVS) compare --scenarios e4-circle-large --params $(PRE11) --predictors cs-akf-adaptive --sweep predictors.cs-akf-adaptive.params.sigma_min_sq=0.001,0.1,1,10,100 --out out/reproduction/paper000-e4-floor
	$(PREDVS) compare --scenarios e1-line,e2-accel-jump,e3-zigzag,e4-circle,e4-circle-large --params $(PRE11) --predictors $(FUZZY_LAYERS) --out out/reproduction/paper000-fuzzy-layers
	$(PREDVS) compare --scenarios e1-line,e2-accel-jump,e3-zigzag --predictors $(PAPER000) --params $(PRE11) --set noise.model=none --runs 1 --out out/reproduction/paper000-no-noise
	$(PREDVS) compare --scenarios ibvs-moving-target --params $(PRE11) --predictors $(STKF_TUNING) --out out/reproduction/closed-loop-stkf
	$(PREDVS) compare --scenarios e12-discontinuity-2ms,e12-smooth --predictors st-akf-pm --sweep predictors.st-akf-pm.params.pm_band=3,4,5,6 --out out/reproduction/paper004-band
	@mkdir -p out/reproduction
	$(BUILD_DIR)/tests/predictors_tests --gtest_filter='Stkf.OcclusionPredictsOnlyThenReinitialisesWhenPExceedsThreshold' | tee out/reproduction/paper001-e7-reinit.txt

# Debian packages of the build (cmake/PredvsPackage.cmake): $(BUILD_DIR)/predvs_<version>_<arch>.deb
# (the CLI and its data) and predvs-dev_<version>_<arch>.deb (headers, static libraries, CMake
# package). deb-check installs the first into a fresh debootstrapped Debian 12 and runs it there
# (root, network; about 6 minutes: docs/PERFORMANCE.md "The Debian package on a fresh Debian 12").
deb: build
	cd $(BUILD_DIR) && cpack -G DEB

deb-check: deb
	bash scripts/check-deb-fresh.sh $(BUILD_DIR)/predvs_*_$$(dpkg --print-architecture).deb

clean:
	rm -rf $(BUILD_DIR) out
