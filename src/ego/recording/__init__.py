"""Recordings: the MCAP format of ``ego run --record``, its writer and its reader."""
