"""What the three faces share: the robot a controller opens, its run options, integer tags.

The faces themselves keep their public names: :mod:`ego.controller` (Webots' Python API),
:mod:`ego.webots` (Webots' C API) and :mod:`ego.overo` (E-GO's C API).
"""
