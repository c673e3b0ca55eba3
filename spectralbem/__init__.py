"""spectralbem."""
