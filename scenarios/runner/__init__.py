"""The job runner shared by the paper units and the bench: executors, the unit store and its codec."""
