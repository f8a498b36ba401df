"""A robot served as a Zenoh node (``ego serve --zenoh``)."""
