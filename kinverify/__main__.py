import sys

from kinverify.cli import main

sys.exit(main())
