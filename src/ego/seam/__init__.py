"""The seam's plain types, below both the core and the wire: a firmware's profile, a
step's batch of requests, the channel every backend opens and its statistics, and the
checks of a value (``check_int``) every layer shares. Imports nothing of ego but
:mod:`ego.errors`."""
