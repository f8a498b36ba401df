"""The control session both servers run, and ``ego serve``'s wire session over it (no I/O).

:mod:`~ego.servers.sessions.control` holds the lease, the deadman and the one call in
flight for the socket server and the Zenoh node alike; :mod:`~ego.servers.sessions.session`
is fed ``ego serve``'s frames and returns frames and actions (h11's shape), with the
handshake (gate), the ended sessions (ended) and the replies' wording (replies)."""
