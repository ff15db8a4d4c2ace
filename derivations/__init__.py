"""Exact derivations (sympy) of every constant and formula the LPV uses.

One module a topic: ``solid_angles``, ``sh``, ``rsm``, ``corrections`` (with
``implementation_switches``), ``propagation``, ``occlusion``, ``errata``. Each exposes
``results()``; :mod:`derivations.registry` collects them under dotted names
(``get("solid_angles.front_face")``), and :mod:`derivations.codegen` turns those with a
GLSL name into ``shaders/generated/constants.glsl`` and ``explorer/lpv/constants.py``,
and all of them into ``explorer/derived_table.py`` (LaTeX, statement, value: what the
window shows, without sympy).
"""
