"""The lesson ``lpv-explorer lessons new NAME`` writes to start from: two steps, a
figure, a try-this with its check, a mark, a prediction, in the layout
docs/AUTHORING.md describes (its example is this text, put there by
``python -m explorer.lessons.guide``)."""

from __future__ import annotations

import json
import re
import unicodedata

from explorer.lessons.reader import ID_PATTERN

TEMPLATE = """\
id = "{id}"
title = {title}
summary = \"\"\"The bounce of light a light propagation volume adds, and how far it travels \\
with each propagation step.\"\"\"
scene = "cornell"                      # a built-in scene, or a scene file or mesh beside this file

[settings]                             # every step starts from these
grid_size = 16

[[steps]]
title = "The bounce of light"
text = '''
The view shows the Cornell box lit by a spot light that points down. The ceiling is lit
all the same: light bounces off the floor and the walls, and the grid of the **light
propagation volume** carries it up. The ceiling gathers
{{{{mark.ceiling.irradiance:.3f}}}} W/m² of it now.

A lit patch sends its light out as a clamped cosine around its normal, which the grid
stores in spherical harmonics of order $l \\le 1$; drag the normal to see how close they come:

{{{{figure:lobe}}}}
'''
view = "final"
[[steps.figures]]
kind = "clamped-cosine"
id = "lobe"
normal_deg = 30
caption = "The clamped cosine (white) and its SH projections: 4 coefficients, blue; 9, orange."
[[steps.marks]]
id = "ceiling"
label = "ceiling: lit by the bounce"
at = [0.0, 0.99, -0.3]
normal = [0, -1, 0]
[[steps.checks]]
claim = "the ceiling is lit by the bounce although the spot points down"
value = "mark.ceiling.irradiance"
op = ">"
than = 0.1

[[steps]]
title = "One cell per step"
text = '''
Propagation moves the light one cell per step, {{{{settings.iterations}}}} steps of
{{{{frame.cell_size:.3f}}}} m cells here. The view shows the indirect light alone.
Fewer steps stop the light before it reaches the ceiling: {{{{try:1}}}}
'''
view = "indirect"
[[steps.marks]]
id = "ceiling"
label = "ceiling"
at = [0.0, 0.99, -0.3]
normal = [0, -1, 0]
[[steps.try_this]]
control = "iterations"
value = 2
prompt = \"\"\"With two steps the light from the floor stops short of the ceiling, which \\
gets {{{{mark.ceiling.irradiance:.3f}}}} W/m² now.\"\"\"
[steps.try_this.predict]               # asked before the button shows the answer
question = "With two steps instead, the ceiling gets"
choices = ["more light", "less light"]
answer = 2
[[steps.checks]]
claim = "two steps carry less light to the ceiling"
value = "mark.ceiling.irradiance"
over = "mark.ceiling.irradiance"
over_before_try = true
after_try = 1
op = "<"
than = 1
"""


def slug(name: str) -> str:
    """``name`` as a lesson id: lower case, accents dropped, words joined by '-'."""
    plain = unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode()
    return re.sub(r"[^a-z0-9]+", "-", plain.lower()).strip("-")


def new_lesson(name: str) -> tuple[str, str]:
    """(id, file text) of a new lesson called ``name``; ValueError when no id can be
    made from it."""
    lesson_id = slug(name)
    if not ID_PATTERN.match(lesson_id):
        raise ValueError(f"{name!r} gives no lesson id (letters or digits, words joined "
                         "by '-')")
    title = " ".join(name.split()) or lesson_id
    # a TOML basic string is a JSON string (quotes and backslashes escaped)
    text = json.dumps(title[:1].upper() + title[1:], ensure_ascii=False)
    return lesson_id, TEMPLATE.format(id=lesson_id, title=text)
