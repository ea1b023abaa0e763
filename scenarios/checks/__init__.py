"""The closed-form checks of the sensor models, one module per part (``core`` holds the check record)."""
