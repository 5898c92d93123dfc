// An empty translation unit: a static library needs at least one object.
