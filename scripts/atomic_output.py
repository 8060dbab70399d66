"""Writing a plot or a text file whole or not at all, as anticrack writes its own files
(util/atomic_file.h): to NAME.tmp.EXT, then renamed over NAME (atomic within a file system), so that
a run killed while plotting never leaves a torn PNG or report (docs/resume.md)."""
import os


def _temporary(path):
    stem, extension = os.path.splitext(path)
    return f"{stem}.tmp{extension}"  # keeps the extension, from which matplotlib takes the format


def save_figure(figure, path, **options):
    """figure.savefig(path, **options), atomically."""
    temporary = _temporary(path)
    figure.savefig(temporary, **options)
    os.replace(temporary, path)


def write_text(path, text):
    """The file `path` holding `text`, atomically."""
    temporary = _temporary(path)
    with open(temporary, "w") as f:
        f.write(text)
    os.replace(temporary, path)
