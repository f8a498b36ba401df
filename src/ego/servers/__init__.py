"""Servers: a robot served to others. The control session (sans-I/O) and its socket and
Zenoh adapters, the robot service they share, the supervisor, the dashboard."""
