"""Recordings and the readers of real logs, below both :mod:`gyrobench.sim` and :mod:`gyrobench.analysis`.

Modules
-------
recording
    :class:`~gyrobench.io.recording.Recording` (channels, truth, metadata) and its HDF5 and CSV
    forms.
logs
    readers of real IMU logs (EuRoC, Kalibr, ROS CSV, plain CSV) into arrays with units.
"""
