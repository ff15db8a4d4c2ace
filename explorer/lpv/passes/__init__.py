"""The GPU passes of the LPV frame, one module per pass (its programs, targets and
``run``); each is checked against its numpy twin in :mod:`explorer.lpv.twin`. The stages
(:mod:`explorer.lpv.stages`) call them in the order the stage list declares."""
