from porenet.cli import main

raise SystemExit(main())
