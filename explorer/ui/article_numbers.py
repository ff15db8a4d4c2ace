"""What a lesson step's text reads: the live context its numbers come from, the audit and
reference measurement it needs, and which numbers change while the frame converges."""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.figure_params import FIGURE_KINDS
from explorer.lessons import Step, live_values
from explorer.lessons import text as lesson_text

if TYPE_CHECKING:
    from explorer.ui.state import AppState


def live_context(state: AppState, step: Step) -> live_values.LiveContext:
    """What the step's placeholders read now (figures: those the step quotes)."""
    from explorer.ui.panels.error import current_stats, want_truth

    rt = state.runtime
    if uses_truth(step):
        want_truth(state)
    figures = {}
    wanted = {name.split(".")[1] for text in step_texts(step)
              for name, _ in lesson_text.placeholders(text) if name.startswith("figure.")}
    if wanted:
        from explorer.ui.figures import FIGURES

        with figure_context(state).showing(state) as context:
            for spec in step.figures:
                if spec.instance_id in wanted:
                    kind = FIGURES[spec.kind]
                    instance = context.state_for(spec.instance_id, spec.kind, spec.params,
                                                 kind.make_state)
                    figures[spec.instance_id] = kind.readouts(spec.params, instance, context)
    return live_values.LiveContext(settings=state.settings, result=rt.frame.result,
                                   error=current_stats(state), figures=figures,
                                   renderer=rt.services.gl_renderer,
                                   marks={mark.id: mark for mark in step.marks})


def step_texts(step: Step) -> list[str]:
    return [step.text] + [t.prompt for t in step.try_this] + [f.caption for f in step.figures]


AUDIT_FIGURES = {kind.name: kind.audit for kind in FIGURE_KINDS if kind.audit != "off"}
"""Figure kinds that plot the energy audit of the frame, and the audit mode
(explorer.lpv.audit.AUDIT_MODES) each needs (``FigureKindDecl.audit``)."""


def uses_audit(step: Step) -> str:
    """The audit mode the step needs (a figure of :data:`AUDIT_FIGURES` or an ``audit.*``
    number, :func:`explorer.lessons.live_values.audit_needed`): the window asks the pipelines to
    measure that much while it shows; ``off`` when it quotes none."""
    from explorer.lpv.audit import strongest_audit

    return strongest_audit(
        *[AUDIT_FIGURES.get(spec.kind, "off") for spec in step.figures],
        *[live_values.audit_needed(name) for text in step_texts(step)
          for name, _ in lesson_text.placeholders(text)])


def uses_truth(step: Step) -> bool:
    """The step quotes a number measured against Mitsuba (``error.mitsuba_*``,
    ``error.reference_mitsuba_*``)."""
    return any(name.startswith(("error.mitsuba_", "error.reference_mitsuba_"))
               for text in step_texts(step) for name, _ in lesson_text.placeholders(text))


def uses_error(step: Step) -> bool:
    return any(name.startswith("error.") for text in step_texts(step)
               for name, _ in lesson_text.placeholders(text))


def figure_context(state: AppState):
    """The figures' shared context (their interactive state), kept on the app state."""
    context = state.lesson_figures
    if context is None:
        from explorer.ui.figures import FigureContext

        context = FigureContext()
        state.lesson_figures = context
    return context


def pending_audit(name: str, context: live_values.LiveContext,
                   figure_ids: tuple[str, ...]) -> str | None:
    """The reason an ``audit.*`` number waits for (its audit mode did not measure it),
    closing the tooltip's parenthesis; None for other numbers or no frame yet."""
    if not name.startswith("audit.") or context.result is None:
        return None
    reason = live_values.pending_reason(name, context, figure_ids)
    return None if reason is None else reason + ")"


PROVISIONAL = "≈"
"""Marks a number read from a frame that is still converging (the view says
"propagating k/N"): it changes until the frame has converged; its tooltip says so. (No
line of text announces it: the article would move under the reader's mouse each time a
try-this starts a new frame.)"""


def provisional(quantity) -> bool:
    """Whether ``quantity`` is read from the pipeline's frame (and so changes while it
    converges): frame and audit numbers; not settings, constants, the Error panel's
    measurement or a figure's own readout."""
    return quantity.source in ("frame", "audit") and not quantity.constant
