"""Load capacity of gear pairs: pitting and tooth root bending safety factors.

* :mod:`~reducerlab.rating.iso6336_3`: ISO 6336-3:2019 method B, tooth root stress
  (``Y_F``, ``Y_S``, ``h_Fe``, ``s_Fn``, ``rho_F``, ``alpha_Fen`` of a generated
  :class:`~reducerlab.geometry.spur.SpurGear`: ``gear_tooth_form``, ``spur_tooth_form``;
  the internal gears' rack construction; ``Y_beta``, ``Y_B``, ``Y_DT``, ``Y_NT``,
  ``Y_deltarelT``, ``Y_RrelT``, ``Y_X``);
* :mod:`~reducerlab.rating.iso6336_2`: ISO 6336-2:2019 method B, pitting (``Z_H``,
  ``Z_E``, ``Z_eps``, ``Z_beta``, ``Z_B``/``Z_D``, ``sigma_H0``, ``Z_NT``, ``Z_L``,
  ``Z_v``, ``Z_R``);
* :mod:`~reducerlab.rating.material`: gear materials (ISO 6336-5 limits) and the rating
  conditions with their documented defaults;
* :mod:`~reducerlab.rating.cylindrical`: the whole chain for spur, internal and
  (virtual) helical pairs, every factor with its clause;
* :mod:`~reducerlab.rating.iso10300_1`, :mod:`~reducerlab.rating.iso10300_2`,
  :mod:`~reducerlab.rating.iso10300_3`: ISO 10300:2023 method B1 for bevel gears without
  offset (virtual gears, ``l_bm``, ``rho_rel``, ``K_v-B``, ``K_Hbeta-C``, ``K_Halpha-B``;
  ``Z_M-B``, ``Z_LS``, ``Z_KP``; ``Y_Fa``, ``Y_Sa``, ``Y_eps``, ``Y_BS``, ``Y_LS``);
* :mod:`~reducerlab.rating.bevel`, :mod:`~reducerlab.rating.bevel_b1`: a bevel pair by
  method B1 (or its virtual cylindrical gears by ISO 6336, ``method="iso6336"``).

Layer: stands on ``geometry/`` (and ``errors``); the analysis and command layers stand
on it.
"""
