"""Inputs: the forcing signals a run receives (`signals`: none, harmonic, sweep, from_csv,
kanai_tajimi, as `pidamper.forcing.harmonic(...)`), synthetic and recorded ground motions
(`ground_motion`) and their response spectra and intensity measures (`spectra`).  It imports nothing
of the rest of the harness."""
from .base import Forcing
from .signals import fema_p695, from_csv, harmonic, kanai_tajimi, none, sweep

__all__ = ["Forcing", "from_csv", "harmonic", "kanai_tajimi", "none", "sweep"]
