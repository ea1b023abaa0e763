"""pytest plugin (entry point ``pytest11``) giving the ``gyrobench_bench`` fixture.

Placeholder: the fixture lands with the bench (issue 7).
"""
