"""hydrokit: free-decay identification, coefficient estimation, 6-DOF models and control
for underwater vehicles.

Layers (see docs/architecture.md): core -> identify / estimate / model -> simulate ->
io / plot -> report -> cli. Units are SI and radians everywhere inside the package.
"""

__version__ = "0.1.0"

from hydrokit.errors import HydrokitError, InputError

__all__ = ["HydrokitError", "InputError", "__version__"]
