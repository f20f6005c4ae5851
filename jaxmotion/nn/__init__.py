"""Network layers shared by the models: pure-function GRU (``lax.scan``) and Transformer layers over explicit
parameter pytrees in PyTorch's layout, and the ST-GCN recogniser (Flax)."""
