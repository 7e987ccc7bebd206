// placeholder: rosyhatch inspect (issue 6)
