# metabezier: the commands a user runs. `make help` lists them.
CARGO ?= cargo
BIN := target/release/metabezier
SPECS := experiments

.PHONY: help build quick test bench reproduce-ch4 reproduce-all fmt lint clean-results

help:
	@echo "make quick          run experiments/quick.toml (seconds) into results/quick/"
	@echo "make test           the whole test suite, rustfmt check and clippy -D warnings"
	@echo "make bench          criterion benchmarks (optimiser overhead per evaluation)"
	@echo "make reproduce-ch4  the chapter-4 benchmark campaign into results/ch4_benchmarks/"
	@echo "make reproduce-all  every chapter that exists so far"

build:
	$(CARGO) build --release --locked

$(BIN): build

quick: build
	$(BIN) run $(SPECS)/quick.toml --resume

test:
	$(CARGO) fmt --all -- --check
	$(CARGO) test --release --locked
	$(CARGO) clippy --release --locked --all-targets -- -D warnings

bench:
	$(CARGO) bench --locked --bench optimisers

reproduce-ch4: build
	$(BIN) run $(SPECS)/ch4_benchmarks.toml --resume

reproduce-all: reproduce-ch4

fmt:
	$(CARGO) fmt --all

lint:
	$(CARGO) clippy --all-targets -- -D warnings

clean-results:
	rm -rf results/quick results/ch4_benchmarks
