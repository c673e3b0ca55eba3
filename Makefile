# All targets install into and run from a project-local virtual environment (.venv).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
JOBS   ?= 2

.PHONY: all venv demo test validate bench figures docs lint clean

all: test

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

venv: $(STAMP)

demo: $(STAMP)
	mkdir -p demo_out
	$(BIN)/spectralbem run cases/rubber_rough.toml -o demo_out/demo.nc
	MPLBACKEND=Agg $(BIN)/spectralbem plot demo_out/demo.nc -o demo_out/demo.png
	@echo "next: $(BIN)/spectralbem run cases/<scene>.toml -o x.nc && $(BIN)/spectralbem plot x.nc"

test: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python -m pytest -n $(JOBS) --dist loadgroup -q

validate: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python -m spectralbem.validate -o docs

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[test,bench]'
	$(BIN)/python bench/run.py
	$(BIN)/python bench/pk_restart.py
	$(BIN)/python bench/krylov.py
	$(BIN)/python bench/viscoelastic.py
	$(BIN)/python bench/viscoelastic.py --starts
	$(BIN)/python bench/viscoelastic.py --robustness
	$(BIN)/python bench/viscoelastic.py --adhesive
	$(BIN)/python bench/viscoelastic.py --large
	$(BIN)/python bench/scaling.py
	$(BIN)/python bench/sphere.py 512 default 6
	$(BIN)/python bench/sphere_release_rates.py --delayed-kernel cell sampled
	$(BIN)/python bench/oblique_front.py
	$(BIN)/python bench/oblique_front.py --a0 0.2 --cells 8 --slope 3 --out bench/oblique_front_slope3.json
	$(BIN)/python bench/oblique_front.py --a0 0.2 --cells 4 8 16 32 --slope 0 --out bench/oblique_front_axis.json
	$(BIN)/python bench/front_lake.py
	$(BIN)/python bench/accuracy.py
	$(BIN)/python bench/relaxation_length.py
	$(BIN)/python bench/sweep2d.py
	$(BIN)/python bench/sweep2d.py --rough 512
	$(BIN)/python bench/oned.py
	$(BIN)/python bench/rough_convergence.py
	$(BIN)/python bench/rough_convergence.py --materials elastic --extrapolate-a0 --sizes 256 512
	$(BIN)/python bench/rough_convergence.py --materials elastic --extrapolate-a0 --sizes 256 512 --coarse-start
	$(BIN)/python bench/rough_convergence.py --materials sls --sizes 256 512 --coarse-start
	$(BIN)/python bench/rough_convergence.py --materials sls --path stepped --sizes 128 256 512
	$(BIN)/python bench/rough_convergence.py --materials sls --path stepped --sizes 256 512 --front-tol 0.25
	$(BIN)/python bench/rough_convergence.py --materials sls --path stepped --sizes 256 --front-tol 0.125
	$(BIN)/python bench/state_spread.py --masks --length 1e-3 --sizes 256 --front-tol 0.5 0.25 0.125
	$(BIN)/python bench/state_spread.py --masks --length 2e-3 --sizes 512 --front-tol 0.5 0.25 0.125
	$(BIN)/python bench/state_spread.py --length 2e-3 --sizes 512 --front-tol 0.5 0.25
	$(BIN)/python bench/state_ensemble.py --sizes 256 512
	$(BIN)/python bench/front_anatomy.py --sizes 128 256 512

figures: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python cases/figures_1d.py
	MPLBACKEND=Agg $(BIN)/python cases/example_figures.py

docs: $(STAMP)
	$(BIN)/python docs/generate_reference.py

lint: $(STAMP)
	$(BIN)/ruff check spectralbem tests bench cases docs

clean:
	rm -rf $(VENV) demo_out .pytest_cache
