"""Paper 001 (scenario ``mems_scale_factor``): to be moved here from gyrobench.scenarios.mems_scale_factor."""
