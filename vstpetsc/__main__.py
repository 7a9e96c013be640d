import sys

from vstpetsc.cli import main

sys.exit(main())
