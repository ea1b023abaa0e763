"""Paper 003 (scenario ``ifog_thermal``): to be moved here from gyrobench.scenarios.ifog_thermal."""
