"""Models: generators (ACTOR, ActFormer, Neural Marionette, ODMO, Action2Motion) and recognisers."""
