# restir — C99 reference renderer for the ReSTIR family.
# Needs only a C99 compiler (gcc or clang), make, libc, libm and pthreads.
#
#   make                 build build/restir
#   make run             the oracle demo: ReSTIR PT vs path tracer on Cornell and ajar, check verdicts (out/)
#   make test            build and run the test suite (ends with "N passed, N failed")
#   make test-long       the longer statistical suites too
#   make test-data       load every file of ../shared/data (real-world OBJ/MTL/PFM)
#   make test-cluster    the GNU parallel and Slurm recipes of docs/reference-renders.md (root)
#   make bench           benchmarks, machine-readable JSON on stdout
#   make mutation-score  planted bugs of tests/mutants vs make test (slow; MUTANT_FLAGS=--long)
#   make test-extremes   the extremes suite, double and float builds (docs/precision.md)
#   make fuzz            libFuzzer harnesses of tests/fuzz (clang; FUZZ_RUNS, FUZZ_TARGETS)
#   make valgrind        the quick suite's CLI paths under valgrind memcheck
#   make tradeoffs       docs/tradeoffs.md: time against error for every knob (~20 min)
# Options: CC=clang  PRECISION=float  SANITIZE=1  WERROR=1  DEBUG=1  SEED=n  T=filter  BUILD=dir  LTO=1  NATIVE=1
#   LTO=1 links with link-time optimisation (cross-file inlining; the same output bit for
#   bit, 3-9% faster, but every relink takes ~10 s on an idle machine, ~40 s under load,
#   instead of ~1 s: docs/performance.md).
#   NATIVE=1 compiles the same portable C for this machine's vector ISA (-march=native,
#   build/native): bit-identical output (-ffp-contract=off still forbids contracting
#   products into FMAs), faster traversal (docs/performance.md, "BVH traversal").
#   DEBUG=1 checks the estimator's invariants after every GRIS step and aborts with
#   file:line on a failure (include/restir/core/invariant.h; docs/statistics.md).

PRECISION ?= double
SANITIZE ?= 0
FUZZ ?= 0
WERROR ?= 0
DEBUG ?= 0
NATIVE ?= 0

ifeq ($(SANITIZE),1)
BUILD_SAN := /san
endif
ifeq ($(PRECISION),float)
BUILD_PREC := /float
endif
ifeq ($(DEBUG),1)
BUILD_DEBUG := /debug
endif
# FUZZ_SAN=undefined: libFuzzer with UBSan only (no ASan), several times the
# executions per second, for the bulk of a long run; its corpus is then replayed
# under ASan+UBSan (docs/fuzzing.md).
FUZZ_SAN ?= address,undefined
ifeq ($(FUZZ),1)
BUILD_FUZZ := /fuzz$(if $(findstring address,$(FUZZ_SAN)),,-ubsan)
endif
LTO ?= 0
ifeq ($(LTO),1)
BUILD_LTO := /lto
endif
ifeq ($(NATIVE),1)
BUILD_NATIVE := /native
endif
BUILD ?= build$(BUILD_SAN)$(BUILD_PREC)$(BUILD_DEBUG)$(BUILD_FUZZ)$(BUILD_LTO)$(BUILD_NATIVE)

CFLAGS ?= -O2
CFLAGS += -std=c99 -Wall -Wextra -Wpedantic -ffp-contract=off -D_POSIX_C_SOURCE=200809L
CPPFLAGS += -Iinclude -MMD -MP
LDLIBS += -lm -lpthread
ifeq ($(PRECISION),float)
CPPFLAGS += -DRESTIR_REAL_FLOAT
endif
ifeq ($(SANITIZE),1)
CFLAGS += -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
LDFLAGS += -fsanitize=address,undefined
endif
ifeq ($(FUZZ),1)
# libFuzzer instrumentation for `make fuzz` (clang only; docs/fuzzing.md).
CFLAGS += -g -fsanitize=fuzzer-no-link,$(FUZZ_SAN) -fno-omit-frame-pointer -fno-sanitize-recover=undefined
LDFLAGS += -fsanitize=$(FUZZ_SAN)
endif
ifeq ($(WERROR),1)
CFLAGS += -Werror
endif
ifeq ($(LTO),1)
# gcc: -flto=auto runs the link-time code generation in parallel (and without a warning)
LTO_FLAG := $(if $(findstring clang,$(CC)),-flto,-flto=auto)
CFLAGS += $(LTO_FLAG)
LDFLAGS += $(LTO_FLAG)
endif
ifeq ($(NATIVE),1)
CFLAGS += -march=native
endif
ifeq ($(DEBUG),1)
CPPFLAGS += -DRESTIR_DEBUG
CFLAGS += -g
endif

LIB_SRC := $(sort $(filter-out src/cli/main.c,$(wildcard src/*/*.c)))
LIB_OBJ := $(LIB_SRC:%.c=$(BUILD)/%.o)
TEST_SRC := $(sort $(wildcard tests/*.c))
# The fuzz targets (tests/fuzz/, docs/fuzzing.md) are plain functions in the test binary.
FUZZ_SRC := $(sort $(wildcard tests/fuzz/*.c))
TEST_OBJ := $(TEST_SRC:%.c=$(BUILD)/%.o) $(FUZZ_SRC:%.c=$(BUILD)/%.o)

.PHONY: fuzz fuzz-build valgrind tradeoffs
.PHONY: all run test test-long test-data bench clean results results-temporal results-stochastic results-correlation mutation-score results-mutations
all: $(BUILD)/restir

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/librestir.a: $(LIB_OBJ)
	@rm -f $@
	@echo "AR $@"
	@$(AR) rcs $@ $^

$(BUILD)/restir: $(BUILD)/src/cli/main.o $(BUILD)/librestir.a
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS)

# The test registry is generated from the TEST(...) / TEST_LONG(...) lines, so a new
# test is a new function and nothing else.
$(BUILD)/test_registry.h: $(TEST_SRC)
	@mkdir -p $(dir $@)
	@sed -n -e 's/^TEST(\([A-Za-z0-9_]*\)).*/X(\1, 0)/p' -e 's/^TEST_LONG(\([A-Za-z0-9_]*\)).*/X(\1, 1)/p' $(TEST_SRC) > $@.tmp
	@mv $@.tmp $@

$(BUILD)/tests/test_main.o: $(BUILD)/test_registry.h
# The paired power tests (tests/test_power_*.c) run a reduced configuration in the float,
# sanitizer and debug builds: a quarter of their runs, the same code paths, a weaker but still
# honest test (bench.h BENCH_RUNS; docs/statistics.md "Power table"). Full in the default build.
ifneq ($(PRECISION)$(SANITIZE)$(DEBUG),double00)
TEST_REDUCED := -DRESTIR_TEST_REDUCED
endif
$(BUILD)/tests/%.o: CPPFLAGS += -I$(BUILD) -Itests -DRESTIR_BIN='"$(BUILD)/restir"' -DRESTIR_TMP='"$(BUILD)/test-tmp"' $(TEST_REDUCED)

$(BUILD)/tests/run: $(TEST_OBJ) $(BUILD)/librestir.a
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS)

# The oracle in 2.5 minutes: ReSTIR PT vs the path tracer at equal time on two scenes, FLIP against a
# reference, and the `check` verdict (scripts/demo.sh; docs/tour.md).
run: $(BUILD)/restir
	sh scripts/demo.sh out $(BUILD)/restir

test: $(BUILD)/restir $(BUILD)/tests/run
	$(BUILD)/tests/run $(if $(SEED),--seed $(SEED)) $(T)

test-long: $(BUILD)/restir $(BUILD)/tests/run
	$(BUILD)/tests/run --long $(if $(SEED),--seed $(SEED)) $(T)

test-data: $(BUILD)/restir
	sh tests/test-data.sh $(BUILD)/restir ../shared/data

# The GNU parallel and Slurm job-array recipes of docs/reference-renders.md, run as written
# (scaled down) on a one-node Slurm of its own (scripts/test-cluster.sh; needs root and
# Debian's parallel, slurm-wlm, munge, else exit 2; about a minute; not part of make test/CI).
.PHONY: test-cluster
test-cluster: $(BUILD)/restir
	sh scripts/test-cluster.sh $(BUILD)/restir

bench: $(BUILD)/restir
	$(BUILD)/restir bench all

# The hostile-case table (issue 27): every hostile input through the binary, its exit
# status, message and leftovers (scripts/hostile.sh; ~10 s; `make test` runs it too).
hostile-table: $(BUILD)/restir
	{ sed -n '1,/^<!-- table -->$$/p' docs/hostile-cases.md; HOSTILE_BIN=$(CURDIR)/$(BUILD)/restir sh scripts/hostile.sh; } > docs/hostile-cases.md.tmp && \
	  mv docs/hostile-cases.md.tmp docs/hostile-cases.md

clean:
	rm -rf build out

-include $(LIB_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(BUILD)/src/cli/main.d

# The GRIS claims of docs/results.md (minutes; never part of `make test`).
results: $(BUILD)/restir
	sh scripts/results.sh out/results $(BUILD)

# Temporal reuse, GRIS Fig. 9 (docs/results.md; minutes, never part of `make test`).
results-temporal: $(BUILD)/restir
	sh scripts/results_temporal.sh out/results-temporal $(BUILD)

# Planted bugs (tests/mutants/*.patch) against `make test`: score, catching tests and
# margins (docs/statistics.md, "Mutation score"; about 2 minutes per mutant, not CI).
mutation-score:
	sh scripts/mutation-score.sh $(MUTANT_FLAGS)

results-stochastic: $(BUILD)/restir
	sh scripts/results_stochastic.sh out/results-stochastic $(BUILD)
	UPDATE_DOCS=1 sh scripts/results_stochastic_disocclusion.sh out/results-correlation $(BUILD)

results-correlation: $(BUILD)/restir
	sh scripts/results_correlation.sh out/results-correlation $(BUILD)
# The extremes suite (docs/precision.md): the long form in the double and the float build
# (`make test` runs its short form). extremes-table regenerates docs/precision.md's table
# (scripts/extremes.sh; SEEDS="1 2 3 4 5"; minutes).
.PHONY: test-extremes extremes-table
test-extremes:
	$(MAKE) test-long T=extremes_
	$(MAKE) PRECISION=float test-long T=extremes_

extremes-table:
	UPDATE_DOCS=1 sh scripts/extremes.sh out/extremes

# MCMC mutations, the Mutations claims (docs/results.md; minutes, never part of `make test`).
results-mutations: $(BUILD)/restir
	sh scripts/results_mutations.sh out/results-mutations $(BUILD)

# libFuzzer harnesses of tests/fuzz/ (docs/fuzzing.md): needs clang with libFuzzer.
# One target at a time, FUZZ_RUNS executions each (FUZZ_TARGETS to choose), under nice.
# `make test` runs the same targets on the committed inputs of tests/data/fuzz/.
FUZZ_TARGETS ?= obj mtl scene pfm dump cli exr png inflate
FUZZ_RUNS ?= 2000000
fuzz:
	$(MAKE) FUZZ=1 CC=clang FUZZ_SAN=$(FUZZ_SAN) fuzz-build
	sh scripts/fuzz.sh build/fuzz$(if $(findstring address,$(FUZZ_SAN)),,-ubsan) out/fuzz $(FUZZ_RUNS) $(FUZZ_TARGETS)

fuzz-build: $(FUZZ_TARGETS:%=$(BUILD)/fuzz_%)

$(BUILD)/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_file.c tests/fuzz/fuzz.h $(BUILD)/librestir.a
	$(CC) $(CPPFLAGS) $(CFLAGS) -DFUZZ_LIBFUZZER -fsanitize=fuzzer $(filter %.c,$^) $(BUILD)/librestir.a -o $@ $(LDLIBS)

# The quick suite's CLI paths under valgrind memcheck (minutes; not part of make test).
valgrind: $(BUILD)/restir
	sh scripts/valgrind.sh $(BUILD)/restir

# docs/tradeoffs.md: time against error for every knob (about 20 minutes; docs/tradeoffs.md).
tradeoffs: $(BUILD)/restir
	$(MAKE) PRECISION=float
	sh scripts/tradeoffs.sh out/tradeoffs $(BUILD) build/float
