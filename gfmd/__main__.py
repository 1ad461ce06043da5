import sys

from gfmd_contact.cli import main  # the app layer's CLI; `python -m gfmd` as documented

sys.exit(main())
