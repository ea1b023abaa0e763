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
safety
    the output rule every command applies: no output is an input, only gyrobench's own files are
    replaced (or with --force), foreign folders and databases refused; inputs must be regular files.
"""
