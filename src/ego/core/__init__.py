"""The core: the Robot, its step clock and safe stop, the channel seam, the device transactions.

Nothing here imports a backend, a face, a server or the app; backends reach the core
through :mod:`ego.seam.channel` (the seam) and :mod:`ego.core.ground_truth`.
"""
