"""Studies that run many solves: sweeps and maps (``sweep``), ``mech check``'s runner and pool
(``checking``), ``mech bench`` (``bench``), random draws (``draws``) and extreme values (``extremes``).
Above ``mech.verification``, whose judge decides every verdict; below ``mech.students``."""
