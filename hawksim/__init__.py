"""hawksim: a hawkmoth in vertically ascending flight (MuJoCo + extended UVLM)."""

__version__ = "0.2.0"
