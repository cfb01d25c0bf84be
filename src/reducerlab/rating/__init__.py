"""Load capacity of gear pairs: pitting and tooth root bending safety factors.

* :mod:`~reducerlab.rating.iso6336_3`: ISO 6336-3:2019 method B, tooth root stress
  (``Y_F``, ``Y_S`` from the generated tooth form, ``Y_beta``);

Layer: stands on ``geometry/`` and ``contact/`` (and ``errors``, ``units``); the
analysis and command layers stand on it.
"""
