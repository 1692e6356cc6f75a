"""This checkout, imported as ``mech`` from the folder that holds it.

Python finds a folder named ``mech`` in the working directory before the installed package's
finder (an editable install maps ``mech`` to ``api/``). Without this file that folder would be an
empty namespace package; with it, the checkout behaves as the installed ``mech``: its ``__init__``
is ``api/__init__.py`` and its subpackages (``mech.cli``, ``mech.problems``, ...) are the
checkout's folders. Nothing imports this file when mech is imported from anywhere else.
"""

import os as _os

_here = _os.path.dirname(_os.path.abspath(__file__))
__path__ = [_os.path.join(_here, "api"), _here]
_init = _os.path.join(_here, "api", "__init__.py")
__file__ = _init
with open(_init, encoding="utf-8") as _fh:
    exec(compile(_fh.read(), _init, "exec"))
del _fh, _here, _init, _os
