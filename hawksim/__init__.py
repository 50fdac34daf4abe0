"""hawksim: a hawkmoth in vertically ascending flight (MuJoCo + extended UVLM)."""

__version__ = "0.1.0"
