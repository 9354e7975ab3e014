import sys

from pampipe.cli import main

sys.exit(main())
