# Sphinx configuration of the granary manual (make docs). Markdown pages through MyST, the C API
# from the header through Doxygen's XML and Breathe. The Makefile copies docs/ to
# $(BUILD)/docs/src, adds the generated pages there and passes -W: every warning is an error.
import os
import re

project = "granary"
author = "the granary authors"
copyright = "granary authors, BSD 3-Clause"

_here = os.path.dirname(os.path.abspath(__file__))
_root = os.environ.get("GRAN_SOURCE_DIR", os.path.join(_here, ".."))
with open(os.path.join(_root, "include", "granary.h"), encoding="utf-8") as f:
    _m = re.search(r'#define GRAN_VERSION_STRING "([^"]*)"', f.read())
release = version = _m.group(1) if _m else "unknown"

extensions = ["myst_parser", "breathe"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "tools", "Doxyfile", "_examples", "numbers.md", "reference/fortran-procedures.md"]
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

breathe_projects = {"granary": os.environ.get("GRAN_DOXYGEN_XML", os.path.join(_here, "xml"))}
breathe_default_project = "granary"
breathe_domain_by_extension = {"h": "c"}
primary_domain = "c"
highlight_language = "none"

html_theme = "alabaster"
html_title = "granary %s manual" % release
html_static_path = []
html_theme_options = {"page_width": "1100px", "sidebar_width": "260px"}
