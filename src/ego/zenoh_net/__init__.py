"""Robots as Zenoh nodes: ``ego serve --zenoh``, ``Robot("zenoh://NAME")``, Webots' radio.

Zenoh (eclipse-zenoh) is the pub/sub/query engine ROS 2 also runs on (rmw_zenoh): peer to
peer with no broker, or through routers across networks. ego uses it as a swarm's
network. Modules: :mod:`~ego.zenoh_net.keys` (the key space, documented in
docs/zenoh.md), :mod:`~ego.zenoh_net.sessions` (opening a session; off loopback only
with Zenoh's own authentication), :mod:`~ego.servers.zenoh_node.node` (a robot served as a node),
:mod:`~ego.backends.zenoh_remote` (the ``zenoh://`` backend's Channel),
:mod:`~ego.zenoh_net.radio` (Webots' Emitter and Receiver over Zenoh). ``zenoh`` is
imported only by them, and only when a Zenoh feature is used.
"""
