#!/usr/bin/env bash
# The developer's one-line check, seconds rather than the suite's minutes: lint, types,
# the generated files, and the structure tests (layering, private reads, the stage list,
# module sizes).
#   bash scripts/check.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
py=${PYTHON:-.venv/bin/python}
[ -x "$py" ] || py=python3
"$py" -m ruff check .
"$py" -m mypy
"$py" -m explorer.lessons.guide --check
# the generated files' freshness (what `python -m derivations.codegen --check` says) in the
# same process as the registry's tests: the sympy derivations, 15 s of CPU, computed once
exec "$py" -m pytest -q -p no:xdist tests/test_import_graph.py tests/lpv/test_stage_list.py \
    tests/test_corrections_registry.py tests/test_module_size.py \
    tests/derivations/test_codegen.py::test_committed_files_are_fresh
