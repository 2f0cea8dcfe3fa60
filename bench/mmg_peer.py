"""Where the reference peer Mmg 5.8.0's mmgs is (built by ../shared/peers/build-mmg.sh), for the
benchmarks that run it side by side with anisurf."""
import os
import shutil

# Where `../shared/peers/build-mmg.sh /tmp/mmg-peer` puts it.
DEFAULT_BUILD = "/tmp/mmg-peer/mmg/build/bin/mmgs_O3"


def find_mmgs():
    """mmgs_O3 on PATH, else the peer script's default build; None when neither exists."""
    p = shutil.which("mmgs_O3")
    if p:
        return p
    return DEFAULT_BUILD if os.access(DEFAULT_BUILD, os.X_OK) else None
