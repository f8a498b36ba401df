"""The control session: who holds the robot, the deadman, the dispatch of requests.

Fed frames, returning frames and actions (h11's shape); no I/O."""
