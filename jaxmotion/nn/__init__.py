"""Pure-function network layers shared by the models (recurrent cells via ``lax.scan``, ...)."""
