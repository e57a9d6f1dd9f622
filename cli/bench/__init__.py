"""`rustycs bench`: stepping speed of the bench scenes beside pymunk and Box2D v3, with quality,
compile and start-up times and a scaling series. Each measurement runs in a fresh process (worker)."""
