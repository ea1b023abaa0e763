"""Maps of what a paper leaves open: a device family, the paper-consistent region, each claim over it.

:mod:`.family` (the open parameters with their ranges and sources, the fixed ones, the
space-filling design), :mod:`.run` (the design's units on the shared runner's executors and unit
store), :mod:`.region` (the constraints from the paper's device facts, the region, each claim's
verdict over it, the sensitivity ranking, ``map.json``), :mod:`.figures` (phase diagrams and the
specification curve).
"""
