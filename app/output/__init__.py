"""Writing what Gaitlab makes to files: PNG frames, GIF and MP4 clips, text.

- :mod:`.files`: formats by suffix, early checks, atomic temporary files (and the
  clean-up of those a killed run left behind);
- :mod:`.png`, :mod:`.gif`, :mod:`.video`: the writers. GIF and MP4 take frames one at
  a time (memory does not grow with the clip) and encode on a background thread;
- :mod:`.background`: that thread and its bounded queue.

The user-facing choices (GIF quality, the MP4's crf, the largest size) live in
:mod:`app.choices`.
"""

from .files import (
                    OUTPUT_FORMATS,
                    AtomicPath,
                    OutputFormat,
                    atomic_write_text,
                    cannot_write,
                    check_output_dir,
                    output_format,
                    remove_stale_partials,
                    stale_partials,
                    write_together,
)
from .gif import GIF_MAX_FPS, GIF_PROFILES, GifWriter, gif_durations, gifsicle_path
from .png import write_png
from .video import Mp4Writer, check_crf

__all__ = ["GIF_MAX_FPS", "GIF_PROFILES", "OUTPUT_FORMATS", "AtomicPath", "GifWriter", "Mp4Writer", "OutputFormat",
           "atomic_write_text", "cannot_write", "check_crf", "check_output_dir", "gif_durations", "gifsicle_path",
           "output_format", "remove_stale_partials", "stale_partials", "write_png",
           "write_together"]
