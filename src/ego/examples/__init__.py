"""Example controllers written for Webots, which ``ego run`` runs unchanged."""
