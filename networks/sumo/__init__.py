"""SUMO itself: the libsumo driver that replays the model's runs (:mod:`.driver`), what a
drive is asked and returns (:mod:`.runs`), the libsumo-free placement helpers
(:mod:`.placement`) and the wheel's SUMO binaries (:mod:`.tools`)."""
