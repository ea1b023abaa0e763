"""The base layer: helpers that import nothing else of gyrobench."""
