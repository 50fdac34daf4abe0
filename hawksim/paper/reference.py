"""The paper's published numbers that hawksim compares with (Nguyen et al. 2020, Acta Mech. Sin. 36).

The kinematics of its Table 3 live with the kinematics (:data:`hawksim.insect.kinematics.TABLE3_DEG`), its Table 1
morphology with the morphology (:mod:`hawksim.insect.morphology`).
"""

PAPER_POWER_FIT_W = (0.0702, 0.0215)
"""Nguyen et al. (2020), Sec. 4.1 (Figs. 13-14): mean power P = 0.0702 + 0.0215 V [W, V in m/s]."""

PAPER_TABLE4 = {  # Nguyen et al. (2020) Table 4: UVLM values at the trims (ANN values in parentheses there)
    "L_plus": (0.97, 0.98, 0.99, 0.99, 0.99), "D_plus": (0.0, 0.0, 0.0, 0.0, 0.0),
    "M_plus": (0.0, -0.01, 0.0, 0.0, 0.0), "P_plus": (0.86, 0.96, 1.09, 1.21, 1.34)}
