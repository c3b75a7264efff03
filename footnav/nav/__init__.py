"""Numerics every component may share: rotations, the strapdown step, Kalman kernels, initial
alignment and heading, gait cycles and stance checks, time spans, DTW and clock maps.

Imports only the bottom layer (``footnav.core.types``, ``footnav.core.errors``, ``footnav.core.component``).
"""
