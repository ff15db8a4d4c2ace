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
"$py" -m derivations.codegen --check
"$py" -m explorer.lessons.guide --check
exec "$py" -m pytest -q -p no:xdist tests/test_import_graph.py tests/lpv/test_stage_list.py \
    tests/test_corrections_registry.py tests/test_module_size.py
