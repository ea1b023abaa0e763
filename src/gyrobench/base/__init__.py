"""The base layer: what every layer of gyrobench may use, importing none of them.

Modules
-------
validate
    one-line checks of scalar arguments (finite, positive, a Generator, a sample rate).
ranges
    declarative field specs (:class:`~gyrobench.base.ranges.FieldRange`) and the refusal of a
    value outside them.
memory
    memory estimates, checked before allocating.
atomic
    atomic writes of files and folders.
units
    named conversions between field units and SI.
"""
