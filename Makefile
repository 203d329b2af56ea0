# metabezier: the commands a user runs. `make help` lists them.
CARGO ?= cargo
BIN := target/release/metabezier
SPECS := experiments

.PHONY: bbob-full pycma-parity help build quick test test-browser test-python wheel test-dxf citation python-bench examples peer-kurbo peer-potrace fuzz test-cluster bench overhead speedup bbob cocopp reproduce-ch4 reproduce-ch5 reproduce-ch6 templates-3d cq500 reproduce-all check-reports fmt lint clean-results

help:
	@echo "make build          the release binary, target/release/metabezier (cargo build --release --locked)"
	@echo "make quick          run experiments/quick.toml (seconds) into results/quick/"
	@echo "make test           the whole test suite, rustfmt check and clippy -D warnings"
	@echo "make test-browser   report.html of a quick campaign, an implant run and a fit campaign in headless Chromium (Debian's; installed if missing)"
	@echo "make test-python    the Python package: pip install ./python in a venv, then its pytest suite (PyPI)"
	@echo "make citation       CITATION.cff validated against the Citation File Format schema by cffconvert (pinned in ci/cff-requirements.txt, in a venv; PyPI)"
	@echo "make test-dxf       fit.dxf read back by ezdxf (pinned in ci/dxf-requirements.txt, in a venv): exact control points and weights (PyPI)"
	@echo "make wheel          an abi3 wheel of the Python package (maturin), installed and run in a fresh venv without the Rust toolchain"
	@echo "make python-bench   cost per evaluation of a Python objective called from metabezier, against Rust and numpy (after test-python)"
	@echo "make examples       the library examples (examples/*.rs): your own optimiser and problem in a campaign"
	@echo "make peer-kurbo     kurbo's curve fitting on the horse and the coin, scored by metabezier score"
	@echo "make peer-potrace   potrace (Debian's; installed if missing) against fit on the horse, the coin, the logo and five glyphs: segments, two-sided distance, RMS, CPU ratio"
	@echo "make fuzz           the seeded fuzz loops of tests/fuzz/ with 100,000 mutants per reader (minutes)"
	@echo "make test-cluster   a campaign as a Slurm array job on a private one-node Slurm (root; installs slurm-wlm, munge)"
	@echo "make bench          criterion benchmarks: optimiser overhead per evaluation, cost of E per fitting function"
	@echo "make overhead       each optimiser's CPU time per evaluation against a bare Sphere-30 loop in the same process, and in the first and last tenth of a 2e6-evaluation run (seconds; run it idle)"
	@echo "make memory         the memory guard's estimate against the peak RSS of three campaigns at 1 and 2 threads (minutes; run it idle)"
	@echo "make speedup        1 -> 2 thread speed-up of a 60-run campaign (five alternating runs; run it idle)"
	@echo "make reproduce-ch4  chapter 4: benchmarks, scalability, MHS tuning, with reports (results/ch4_*/)"
	@echo "make reproduce-ch5  chapter 5: curve fitting of real outlines, search-space and MHS studies, both errors (results/ch5_*/)"
	@echo "make reproduce-ch6  chapter 6: cranial implant from CT 0051, artificial-defect validation (results/ch6_cranial/)"
	@echo "make templates-3d   issue 56: the slice-wise, 3D-mirror, rim-fill and straight templates by region on CT 0051's 3D patches (results/templates_3d/), and the real defect with auto3d (results/ch6_cranial_3d/)"
	@echo "make cq500          chapter 6 on a second patient: one-slice validation on the CQ500 slice of pydicom-data (PyPI, in a venv; non-commercial data, not vendored) (results/ch6_cq500/)"
	@echo "make bbob           COCO's bbob suite: 8 optimisers x 24 functions x D = 2, 5, 10, 20, report and COCO logs (results/bbob/)"
	@echo "make bbob-full      the Slurm array script (results/bbob_full.sbatch) for COCO's whole protocol: D = 2, 3, 5, 10, 20, 40, instances 1-15"
	@echo "make pycma-parity   pycma's default on bbob f1-f14 at D = 10 (pinned in tools/pycma-requirements.txt, in a venv; PyPI), then the Rust test that pins its figures"
	@echo "make cocopp         COCO's own post-processing (cocopp, pinned in tools/cocopp-requirements.txt, in a venv) of results/bbob/coco/"
	@echo "make reproduce-all  every chapter: 4, 5 and 6 (about 20 min on 2 cores)"
	@echo "make check-reports  every report under results/ reads on a screen: summary first, < 300 lines, report.html, pictures <= 3,000 px"
	@echo "make fmt            cargo fmt --all"
	@echo "make lint           cargo clippy --all-targets -- -D warnings"
	@echo "make clean-results  delete results/quick, results/ch6_cq500 and the chapter campaigns' results (not results/bbob)"

build:
	$(CARGO) build --release --locked

$(BIN): build

quick: build
	$(BIN) run $(SPECS)/quick.toml --resume
	$(BIN) report results/quick

# The workspace's crates (crates/*) under the binary; the campaign crate is
# also tested alone, where it is built without COCO (the `coco` feature is
# the binary's default), so that `suite = "bbob"` is a located error there;
# the core's normal dependencies hold no I/O, plotting, CLI or C crate.
test:
	$(CARGO) fmt --all -- --check
	$(CARGO) test --release --locked --workspace
	$(CARGO) test --release --locked -p metabezier-campaign --lib
	$(CARGO) check --locked --no-default-features --bin metabezier
	ci/check-core-deps.sh
	$(MAKE) examples
	$(MAKE) peer-kurbo
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --workspace --no-deps --locked
	$(CARGO) clippy --workspace --release --locked --all-targets -- -D warnings
	$(CARGO) clippy -p metabezier-campaign --release --locked --all-targets -- -D warnings

# report.html in headless Chromium (Debian's package, installed when
# missing): the pages of a quick campaign, a small implant run and a small
# fitting campaign load with no console message and their script done, sort
# and switch figures when clicked, and make a screenshot that is not blank
# (ci/browser-test.sh).
test-browser: build
	ci/browser-test.sh $(BIN)

# The Python package (python/): a virtual environment under target/ with the
# pinned build and test tools (PyPI; python3 with venv), the package built
# from the repository by `pip install ./python` (maturin, no build
# isolation, so the pinned maturin builds it), rustfmt and clippy on its
# Rust side, and its pytest suite, which compares with the binary $(BIN).
PY_VENV := target/python-venv
# An abi3 wheel (one for every CPython >= 3.9) by maturin, then installed
# into a fresh venv with only NumPy beside it and run with no Rust
# toolchain on PATH (python/wheel_check/check_wheel.py).
WHEEL_VENV := target/wheel-venv
wheel:
	test -x $(PY_VENV)/bin/python || python3 -m venv $(PY_VENV)
	$(PY_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r python/requirements-test.txt
	rm -rf target/wheels $(WHEEL_VENV)
	cd python && PATH="$(CURDIR)/$(PY_VENV)/bin:$$PATH" maturin build --release --locked --out ../target/wheels
	python3 -m venv $(WHEEL_VENV)
	$(WHEEL_VENV)/bin/python -m pip install --quiet --disable-pip-version-check $$(grep '^numpy==' python/requirements-test.txt)
	$(WHEEL_VENV)/bin/python -m pip install --quiet --disable-pip-version-check --no-index --find-links target/wheels metabezier
	cd /tmp && env -i HOME="$$HOME" PATH=/usr/bin:/bin $(CURDIR)/$(WHEEL_VENV)/bin/python $(CURDIR)/python/wheel_check/check_wheel.py

test-python: build
	test -x $(PY_VENV)/bin/python || python3 -m venv $(PY_VENV)
	$(PY_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r python/requirements-test.txt
	PATH="$(CURDIR)/$(PY_VENV)/bin:$$PATH" $(PY_VENV)/bin/python -m pip install --quiet --disable-pip-version-check --no-build-isolation ./python
	cd python && $(CARGO) fmt -- --check
	cd python && $(CARGO) clippy --release --locked -- -D warnings
	METABEZIER_BIN=$(CURDIR)/$(BIN) $(PY_VENV)/bin/python -m pytest -q python/tests

# fit.dxf read back by a real DXF library: ezdxf audits it and
# ci/check-dxf.py compares every SPLINE with fit.csv (rational cubics,
# rational quadratics, and a glyph's quadratics).
DXF_VENV := target/dxf-venv
# CITATION.cff against the Citation File Format 1.2.0 schema with cffconvert
# (pinned in ci/cff-requirements.txt, in a venv under target/); a copy
# without its authors must be refused, so the check can fail.
CFF_VENV := target/cff-venv
citation:
	test -x $(CFF_VENV)/bin/python || python3 -m venv $(CFF_VENV)
	$(CFF_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r ci/cff-requirements.txt
	$(CFF_VENV)/bin/cffconvert --validate -i CITATION.cff
	@set -e; bad=$$(mktemp -d); grep -v -e '^authors:' -e 'The metabezier developers' CITATION.cff > $$bad/CITATION.cff; \
	  if $(CFF_VENV)/bin/cffconvert --validate -i $$bad/CITATION.cff > /dev/null 2>&1; then \
	    echo "make citation: a CITATION.cff without authors was accepted" >&2; rm -rf $$bad; exit 1; fi; \
	  rm -rf $$bad; echo "make citation: a CITATION.cff without authors is refused"

test-dxf: build
	test -x $(DXF_VENV)/bin/python || python3 -m venv $(DXF_VENV)
	$(DXF_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r ci/dxf-requirements.txt
	@set -e; out=$$(mktemp -d); \
	  $(BIN) fit data/outlines/horse.png --segments 101 --outputs csv,dxf --out $$out/horse > /dev/null; \
	  $(BIN) fit data/outlines/coin.png --function rational-quadratic --segments 6 --outputs csv,dxf --out $$out/coin > /dev/null; \
	  $(BIN) fit font:data/outlines/DejaVuSans.ttf:S --function quadratic --true-breaks --outputs csv,dxf --out $$out/S > /dev/null; \
	  $(DXF_VENV)/bin/python ci/check-dxf.py $$out/horse $$out/coin $$out/S; \
	  rm -rf $$out

# The cost per evaluation of a Python function called from metabezier,
# against pure Rust and numpy alone (and mealpy, NiaPy where installed).
python-bench: test-python
	$(PY_VENV)/bin/python python/bench/overhead.py

# The library examples, each a campaign through the library into a fresh
# directory (tests/optimisers/registry.rs checks their results on 1 and 2 threads).
EXAMPLES := custom_optimiser custom_problem shekel_suite
examples:
	@set -e; for e in $(EXAMPLES); do \
	  out=$$(mktemp -d); \
	  $(CARGO) run --release --locked --example $$e -- $$out/$$e; \
	  test -s $$out/$$e/runs.csv && test -s $$out/$$e/report.md; \
	  rm -rf $$out; \
	done

# kurbo's curve fitting as a peer on the same outlines (examples/kurbo_fit.rs,
# kurbo a dev-dependency), scored by `metabezier score` like our fit.svg and
# potrace's trace; fails if a point is further from kurbo's curves than
# 1.1 times the accuracy asked for.
PEER_INPUTS := data/outlines/horse.png data/outlines/coin.png
peer-kurbo: build
	$(CARGO) build --release --locked --example kurbo_fit
	@set -e; out=$$(mktemp -d); for i in $(PEER_INPUTS); do for a in 1 2; do \
	  target/release/examples/kurbo_fit $$i $$out/k.svg $$a; \
	  $(BIN) score $$i $$out/k.svg | tee $$out/score.txt | tail -1; \
	  awk -v a=$$a '$$1 == "all" { if ($$3 > 1.1 * a) { print "kurbo strays " $$3 " > 1.1 x " a; exit 1 } }' $$out/score.txt; \
	done; done; rm -rf $$out

# potrace on the shape fit traces (examples/shape_pbm.rs writes it as a
# PBM), scored by `metabezier score`, against `fit` at potrace's two-sided
# distance and at its segment count, with the CPU time of whole processes
# (ci/peer-potrace.sh; timing, so not in `make test`): the horse, the coin,
# the logo and five glyphs of the vendored fonts drawn 200 px high
# (examples/glyph_png.rs), unseen by the fitter's tests.
peer-potrace: build
	$(CARGO) build --release --locked --example shape_pbm --example glyph_png
	ci/peer-potrace.sh $(BIN) target/release/examples/shape_pbm target/release/examples/glyph_png

# The fuzz loops of `make test` (a few thousand mutants per reader), longer.
FUZZ_MUTANTS ?= 100000
fuzz:
	METABEZIER_FUZZ_MUTANTS=$(FUZZ_MUTANTS) $(CARGO) test --release --locked --test fuzz -- --test-threads 1

# Installs Debian's slurm-wlm and munge when missing, starts private daemons,
# runs a campaign as an array job (one task requeued mid-run), merges it and
# compares it with a whole run byte for byte; stops the daemons it started.
test-cluster:
	ci/slurm-test.sh

bench:
	$(CARGO) bench --locked --bench optimisers
	$(CARGO) bench --locked --bench fitting
	$(CARGO) bench --locked --bench implant
	$(CARGO) bench --locked --bench instances
	$(CARGO) bench --locked --bench loaders

# Each optimiser's cost per evaluation on Sphere-30 against a bare loop of
# the objective timed in the same process, both on the thread's CPU clock:
# nine alternating rounds, medians and their spread (benches/overhead.rs;
# OVERHEAD_ARGS="--dim 10 --rounds 15" to change). Not part of `make test`.
OVERHEAD_ARGS ?=
overhead:
	$(CARGO) bench --locked --bench overhead -- $(OVERHEAD_ARGS)

CH4 := ch4_tuning ch4_benchmarks ch4_scalability ch4_robustness
# Every reproduce target's report answers the thesis's claims of its
# campaign with their primary rows first (experiments/claims.toml, issue 50).
CLAIMS := --claims $(SPECS)/claims.toml
# Extra `report` arguments per experiment: the tuning grid has 81 MHS cells,
# so its tests compare each setting with classical HS.
REPORT_ARGS_ch4_tuning := --reference "HS (hms=5, hmcr=0.9, bw=0.01)"

# The campaigns with "-tuned" cells; ci/check-tuned.sh checks, after they
# ran, that those cells carry the picks of results/ch4_tuning's report.
TUNED_CH4 := ch4_benchmarks ch4_robustness
TUNED_CH5 := ch5_mhs
CHECK_TUNED := sh ci/check-tuned.sh results/ch4_tuning

# Each campaign resumes where an interrupted one stopped; the report is
# regenerated from the finished results.
reproduce-ch4: build
	$(foreach e,$(CH4),$(BIN) run $(SPECS)/$(e).toml --resume && $(BIN) report results/$(e) $(REPORT_ARGS_$(e)) $(CLAIMS) &&) true
	$(CHECK_TUNED) $(addprefix results/,$(TUNED_CH4))

CH5 := ch5_outlines ch5_search_space ch5_mhs ch5_errors ch5_errors_segments

# The check needs the tuning's picks: ch4_tuning is resumed (nothing to do
# once it is complete) and reported first.
reproduce-ch5: build
	$(foreach e,$(CH5),$(BIN) run $(SPECS)/$(e).toml --resume && $(BIN) report results/$(e) $(REPORT_ARGS_$(e)) $(CLAIMS) &&) true
	$(BIN) run $(SPECS)/ch4_tuning.toml --resume && $(BIN) report results/ch4_tuning $(REPORT_ARGS_ch4_tuning)
	$(CHECK_TUNED) $(addprefix results/,$(TUNED_CH5))

CH6 := ch6_cranial

# The implant pipeline writes every output atomically and the STL only for a
# checked mesh; a rerun overwrites the results.
reproduce-ch6: build
	$(BIN) implant $(SPECS)/ch6_cranial.toml --out results/ch6_cranial

# Issue 56: the four templates compared by region on CT 0051's 3D patches
# (examples/templates_3d.rs, LM fits, about 2 min) and the real defect with
# template_source = "auto3d" (experiments/ch6_cranial_3d.toml).
templates-3d: build
	$(CARGO) run --release --locked --example templates_3d
	$(BIN) implant $(SPECS)/ch6_cranial_3d.toml --out results/ch6_cranial_3d

# Chapter 6 on a second patient: one-slice validation on the CQ500 head CT
# slice 693_UNCR.dcm, used from the PyPI package that ships it (pydicom-data
# 1.0.0, hash-pinned in tools/cq500-requirements.txt) in a virtual environment
# under target/; the slice's sha256 and size are checked, it is copied alone
# into target/cq500/dicom/ (the volume of experiments/ch6_cq500.toml) and
# never into the repository (CQ500 is CC BY-NC-SA 4.0: non-commercial).
# Not part of `make test` (it downloads from PyPI).
CQ500_VENV := target/cq500-venv
CQ500_DIR := target/cq500/dicom
CQ500_SHA256 := cc4cdd599231922ecf63de2ddacf03d51c4588805c9154c2eef1ff49c23b32be
CQ500_BYTES := 525986
cq500: build
	test -x $(CQ500_VENV)/bin/python || python3 -m venv $(CQ500_VENV)
	$(CQ500_VENV)/bin/python -m pip install --quiet --disable-pip-version-check --no-deps --only-binary :all: --require-hashes -r tools/cq500-requirements.txt
	@set -e; \
	  dcm=$$($(CQ500_VENV)/bin/python -c 'import pathlib, data_store; print(pathlib.Path(data_store.__file__).parent / "data" / "693_UNCR.dcm")'); \
	  test -f "$$dcm" || { echo "make cq500: $$dcm is missing from pydicom-data" >&2; exit 1; }; \
	  size=$$(wc -c < "$$dcm"); \
	  test "$$size" -eq $(CQ500_BYTES) || { echo "make cq500: $$dcm has $$size bytes, expected $(CQ500_BYTES)" >&2; exit 1; }; \
	  echo "$(CQ500_SHA256)  $$dcm" | sha256sum --check --quiet - || { echo "make cq500: $$dcm does not have sha256 $(CQ500_SHA256)" >&2; exit 1; }; \
	  rm -rf $(CQ500_DIR); mkdir -p $(CQ500_DIR); cp "$$dcm" $(CQ500_DIR)/693_UNCR.dcm; \
	  echo "693_UNCR.dcm: $$size bytes, sha256 $(CQ500_SHA256) (pydicom-data 1.0.0)"
	$(BIN) implant $(SPECS)/ch6_cq500.toml --out results/ch6_cq500

# The 1 -> 2 thread speed-up of a 60-run campaign: five alternating runs,
# identical runs.csv checked, median speed-up printed (run it idle).
speedup: build
	sh ci/thread-speedup.sh $(BIN)

# COCO's bbob suite through COCO's own code, with its report and COCO-format
# logs for cocopp in results/bbob/coco/ (see docs/guide/bbob.md).
bbob: build
	$(BIN) run $(SPECS)/bbob.toml --resume --coco-log results/bbob/coco
	$(BIN) report results/bbob $(CLAIMS)

# COCO's whole protocol (experiments/bbob_full.toml, 17,280 runs, hours):
# the sbatch script of a Slurm array of BBOB_FULL_TASKS shards. Submit it
# with `sbatch results/bbob_full.sbatch`; its comment names the merge
# command, after which `metabezier report results/bbob_full` reports it.
BBOB_FULL_TASKS ?= 96
bbob-full: build
	mkdir -p results
	$(BIN) slurm $(SPECS)/bbob_full.toml --tasks $(BBOB_FULL_TASKS) > results/bbob_full.sbatch
	@echo "make bbob-full: submit results/bbob_full.sbatch with sbatch, then merge as its comment says"

# pycma's default CMA-ES on bbob f1-f14 at D = 10 (tools/pycma_bbob.py, pycma
# and cocoex pinned, in a venv under target/; not run in CI), whose medians
# tests/optimisers/cmaes_parity.rs pins; then that test, which runs ours. Compare
# target/pycma_bbob.csv's medians with the test's literals by eye.
PYCMA_VENV := target/pycma-venv
pycma-parity:
	test -x $(PYCMA_VENV)/bin/python || python3 -m venv $(PYCMA_VENV)
	$(PYCMA_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r tools/pycma-requirements.txt
	$(PYCMA_VENV)/bin/python tools/pycma_bbob.py > target/pycma_bbob.csv
	sed -n '/# median/,$$p' target/pycma_bbob.csv
	$(CARGO) test --release --locked --test optimisers cmaes_parity -- --nocapture

# COCO's own post-processing of the logs `make bbob` wrote: a virtual
# environment under target/ with cocopp and every package it imports, pinned
# (PyPI; python3 with venv), then cocopp's HTML report in results/bbob/cocopp/.
# Not part of `make test`.
COCOPP_VENV := target/cocopp-venv
cocopp:
	@test -d results/bbob/coco || { echo "make cocopp: results/bbob/coco/ does not exist; run make bbob first" >&2; exit 2; }
	test -x $(COCOPP_VENV)/bin/python || python3 -m venv $(COCOPP_VENV)
	$(COCOPP_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r tools/cocopp-requirements.txt
	$(COCOPP_VENV)/bin/python -m cocopp -o results/bbob/cocopp results/bbob/coco/*
	@echo "cocopp's report: results/bbob/cocopp/index.html"

reproduce-all: reproduce-ch4 reproduce-ch5 reproduce-ch6

# After make reproduce-all (and make bbob): every report.md opens with its
# summary and is under 300 lines, report.html is beside it, and no picture
# is over 3,000 px (ci/check-reports.py, python3's standard library).
check-reports:
	python3 ci/check-reports.py results

fmt:
	$(CARGO) fmt --all

lint:
	$(CARGO) clippy --workspace --all-targets -- -D warnings

clean-results:
	rm -rf results/quick results/ch6_cq500 $(addprefix results/,$(CH4) $(CH5) $(CH6))

# The memory guard's estimate against the peak resident set size of three
# campaign shapes at 1 and 2 threads (ci/measure-memory.sh; GNU time; about
# two minutes, run it idle). Not part of `make test`.
.PHONY: memory
memory: build
	sh ci/measure-memory.sh $(BIN)
