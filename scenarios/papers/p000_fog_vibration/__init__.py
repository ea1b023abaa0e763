"""Paper 000 (scenario ``fog_vibration``): to be moved here from gyrobench.scenarios.fog_vibration."""
