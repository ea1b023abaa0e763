"""Paper 004 (scenario ``rlg_thermal``): to be moved here from gyrobench.scenarios.rlg_thermal."""
